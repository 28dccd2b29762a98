// The cohesive-force stage's GPU state (cuda/cohesive_forces.cu), where the
// whole step (cuda/device_step.cu) can reach it.
#pragma once
#include "bonds/cohesive_pair_kernel.hpp"
#include "cuda/cohesive_forces.hpp"
#include "cuda/device_array.cuh"

namespace engine {

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
  // crack closure (FreezeBonds::apply_crack_closure): the split pairs (opened
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
  void launch_committed(const CohesivePairArrays& a, const double* time, double* f_con_x, double* f_con_y);
};

}  // namespace engine
