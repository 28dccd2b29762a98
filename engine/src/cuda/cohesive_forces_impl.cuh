// The cohesive-force stage's GPU state (cuda/cohesive_forces.cu), where the
// whole step (cuda/device_step.cu) can reach it.
#pragma once
#include "bonds/cohesive_pair_kernel.hpp"
#include "bonds/crack_closure_kernel.hpp"
#include "cuda/cohesive_forces.hpp"
#include "cuda/device_array.cuh"

namespace engine {

// A node's part of the stage after the pairs' kernel: its opened pairs'
// forces summed in ascending pair order (entry 2 j: pair j's + node, 2 j + 1:
// its - node), and its split pairs' crack-closure forces added to its contact
// force in ascending order, as FreezeBonds::apply adds
// them. The stage's node and closure kernels run it; the whole step runs it
// in its one per-node pass (cuda/device_step.cu).
struct CohesiveNodeArrays {
  const int32_t* start;  // the opened pairs of each node
  const int32_t* entry;
  const double* fpx;     // each pair's force on its + node
  const double* fpy;
  double* f_coh_x;
  double* f_coh_y;
  const double* x;       // positions (the closure's gaps)
  const double* y;
  const int32_t* node_plus;
  const int32_t* node_minus;
  const double* fnx;     // each pair's normal
  const double* fny;
  double penalty;
  const int32_t* closure_pair;  // the split pairs of each node
  const int32_t* closure_start;
  const int32_t* closure_entry;
  double* f_con_x;       // the contact forces the closure adds to
  double* f_con_y;
};

ICERUBBLE_HD void cohesive_node_sum(const CohesiveNodeArrays& a, int32_t i) {
  double sx = 0.0, sy = 0.0;
  for (int32_t e = a.start[i]; e < a.start[i + 1]; ++e) {
    const int32_t j = a.entry[e] >> 1;
    const bool minus = a.entry[e] & 1;
    sx += minus ? -a.fpx[j] : a.fpx[j];
    sy += minus ? -a.fpy[j] : a.fpy[j];
  }
  a.f_coh_x[i] = sx;
  a.f_coh_y[i] = sy;
}

ICERUBBLE_HD void crack_closure_node(const CohesiveNodeArrays& a, int32_t i) {
  const int32_t* start = a.closure_start;
  if (start[i] == start[i + 1]) return;
  double sx = a.f_con_x[i], sy = a.f_con_y[i];
  for (int32_t e = start[i]; e < start[i + 1]; ++e) {
    const int32_t k = a.closure_pair[a.closure_entry[e] >> 1];
    double f;
    if (!crack_closure_force(a.x, a.y, a.node_plus[k], a.node_minus[k], a.fnx[k], a.fny[k], a.penalty, f)) continue;
    if (a.closure_entry[e] & 1) {
      sx -= f * a.fnx[k];
      sy -= f * a.fny[k];
    } else {
      sx += f * a.fnx[k];
      sy += f * a.fny[k];
    }
  }
  a.f_con_x[i] = sx;
  a.f_con_y[i] = sy;
}

struct DeviceCohesiveForces::Impl {
  int32_t n_nodes = 0, n_open = 0;
  double dt = 0.0;
  cohesive_law::ForceDirection dir = cohesive_law::ForceDirection::paper;
  DeviceArray<double> x, y, vx, vy, mass, f_x, f_y, f_con_x, f_con_y, fnx, fny, f0, delta_f, delta_m_in, f_n_prev,
      f_t_prev, d_n_prev, d_t_prev, beta, fpx, fpy, delta_m, f_coh_x, f_coh_y, partial, sums;
  DeviceArray<int32_t> pair_point, node_plus, node_minus, open, start, entry;
  DeviceArray<int8_t> failed, mode;
  // per pair (committed steps): state, failure record
  DeviceArray<PairState> pair_state;
  DeviceArray<FailureMode> pair_mode;
  DeviceArray<double> t_fail, x_fail, y_fail, dn_fail, dt_fail;
  // crack closure (FreezeBonds::apply): the split pairs (opened
  // or failed), ascending, and each node's of them in that order (entry 2 j:
  // closure_pair[j]'s + node, 2 j + 1: its - node)
  double penalty = 0.0;
  DeviceArray<int32_t> closure_pair, closure_start, closure_entry;
  cudaStream_t stream = nullptr;
  const int32_t* halt = nullptr;  // the whole step's batch (cuda/halt.cuh); none on its own

  int n_blocks() const;  // of the pair kernel

  // The kernel's arrays: the node state and forces given, the pairs' own.
  CohesivePairArrays arrays(const double* at_x, const double* at_y, const double* at_vx, const double* at_vy,
                            const double* at_f_x, const double* at_f_y, const double* at_f_con_x,
                            const double* at_f_con_y);
  CohesiveHistory history();
  // the stage at its own state, history left (asynchronous)
  void launch();
  // FreezeBonds::apply(commit) of a step starting at *time (GPU memory: a
  // batch's step reads its own) with the kernel arrays `a` (this stage's
  // pair arrays, the step's node state and forces): the pairs' forces into
  // f_coh_x/y, their history and failures written (a pair failed before is
  // passed over), the energy terms into sums (asynchronous).
  // Then the crack closure's forces added to f_con_x/y in the CPU's order
  // (positions a.x, a.y): the caller's contact forces after the pair kernel
  // has read a.f_con_x/y.
  // node_pass false: the node part is left to the caller (node_arrays);
  // term_sums false: the energy terms' sums too (partial, n_blocks()).
  void launch_committed(const CohesivePairArrays& a, const double* time, double* f_con_x, double* f_con_y,
                        bool node_pass = true, bool term_sums = true);
  // The node part's arrays: positions a.x, a.y, the contact forces f_con_x/y.
  CohesiveNodeArrays node_arrays(const CohesivePairArrays& a, double* f_con_x, double* f_con_y);
};

}  // namespace engine
