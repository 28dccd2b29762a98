// The friction stage's GPU state (cuda/friction.cu), where the whole step
// (cuda/device_step.cu) can reach it.
#pragma once
#include "contact/friction_kernel.hpp"
#include "cuda/device_array.cuh"
#include "cuda/friction.hpp"

namespace engine {

// Friction's prediction of a node from its total before friction (its
// inverse masses and end-of-step velocity without friction): the stage's
// predict kernel runs it, the whole step runs it in its node pass
// (cuda/device_step.cu).
struct FrictionPredictArrays {
  const double* mass;
  const uint8_t* constrained;
  const double *vx, *vy, *f_pre_x, *f_pre_y;
  double dt;
  double *imx, *imy, *wx, *wy;
};

ICERUBBLE_HD void friction_predict(const FrictionPredictArrays& p, int32_t i) {
  friction_predict_node(p.mass[i], p.constrained[i], p.vx[i], p.vy[i], p.f_pre_x[i], p.f_pre_y[i], nullptr, nullptr, i,
                        p.dt, p.imx[i], p.imy[i], p.wx[i], p.wy[i]);
}

// Per candidate (index c, the CPU's pair order), what friction reads.
struct FrictionPairArrays {
  const int32_t* node;  // 6 per candidate: contactor's nodes, then target's
  const uint8_t* hit;   // touching
  const double* nc;     // 3 per candidate, where it touches
  const double* nt;
  const double* nx;
  const double* ny;
  const double* fn;
  const uint64_t* key;
};

// What the friction kernels leave in `counts` for the kernels after them and
// for the host: the colours and the colouring's rounds, the touching pairs
// (m), the touching pairs of the colouring kept (-1: none kept; its pairs in
// coloured_tp), whether this launch's touching pairs are those (1: the kept
// colouring is used), how many colourings were made, how many nodes the
// touching pairs have, and that count again where the sweeps keep them in
// shared memory (-1: they do not); the last two made with the colouring.
enum FrictionCount : int32_t {
  c_colours, c_rounds, c_touching, c_coloured, c_same, c_colourings, c_nodes, c_local, n_friction_counts
};

// What the sweeps read of the touching pairs' nodes in shared memory
// (friction.cu's solve_kernel): each such node's local index, by the pair's slot and node
// (node6[6 s + k]), and the nodes in local order (node); first_of[v], the
// first (slot, node) of node v, is INT32_MAX between colourings.
struct LocalNodes {
  int32_t* first_of;  // per node of the mesh
  int32_t* node;      // per local index (room for every touching pair's six)
  int32_t* node6;     // per touching pair's (slot, node)
  int32_t most;       // at most this many in shared memory (most_shared_nodes or fewer: set_shared_nodes)
};

struct DeviceFriction::Impl {
  int32_t n_nodes = 0, n_cand = 0;
  int64_t n_prev = 0;
  double mu = 0.0, dt = 0.0, penalty = 0.0;
  DeviceArray<double> x, y, mass, vx, vy, f_pre_x, f_pre_y, imx, imy, wx, wy, nc, nt, nx, ny, fn, kinv, lambda,
      prev_lambda, f_x, f_y, power;
  DeviceArray<uint8_t> constrained, hit;
  DeviceArray<int32_t> node, colour, counts, start, entry;
  // the touching pairs of a launch (compact_kernel): tp[s] the candidate of
  // slot s, slot_of[tp[s]] = s; per slot and node (6 s + k) the slots of its
  // earlier neighbours there (kEarlier each) and their count (-1: more); per
  // candidate its warm start; counts: FrictionCount
  DeviceArray<int32_t> tp, slot_of, earlier, n_earlier;
  // the touching pairs (tp) of the colouring kept (FrictionCount c_coloured)
  DeviceArray<int32_t> coloured_tp;
  // the touching pairs' nodes numbered for the sweeps' shared memory
  // (LocalNodes): per mesh node, per local number, per (slot, node)
  DeviceArray<int32_t> first_of, local_node, local_node6;
  int32_t shared_nodes = 0;  // at most this many (DeviceFriction::set_shared_nodes)
  // after the colouring: each slot's colour, the touching candidates colour
  // by colour (order), and where colour c starts in it (colour_start[c], c <= colours)
  DeviceArray<int32_t> slot_colour, order, colour_start;
  DeviceArray<double> warm;
  int32_t earlier_list = 0;  // kept in a list per pair and node (DeviceFriction::set_earlier_list)
  DeviceArray<uint64_t> key, prev_key;
  // prev_key is the candidates' keys (WarmStart::per_candidate, the whole
  // step: kept so through list rebuilds), so a pair's warm start is its candidate's entry
  bool warm_by_candidate = false;
  cudaStream_t stream = nullptr;
  const int32_t* halt = nullptr;  // the whole step's batch (cuda/halt.cuh); none on its own
  // hit, nc, nt, nx, ny and fn are written by the step's normal pass (the
  // whole step: the same candidates, positions and penalty), not by launch()
  bool pairs_given = false;
  // imx, imy, wx, wy are written by the whole step's pass over the nodes
  // (friction_predict_node after the force assembly), not by launch()
  bool predicted = false;
  // f_x, f_y hold f_pre_x, f_pre_y already (the whole step's assembly writes
  // both), so friction adds to the touching pairs' nodes alone
  bool totals_given = false;

  FrictionPredictArrays predict_arrays() {
    return {mass.data(), constrained.data(), vx.data(), vy.data(), f_pre_x.data(), f_pre_y.data(), dt,
            imx.data(),  imy.data(),         wx.data(), wy.data()};
  }
  LocalNodes local_nodes() { return {first_of.data(), local_node.data(), local_node6.data(), shared_nodes}; }
  FrictionPairArrays pairs() {
    return {node.data(), hit.data(), nc.data(), nt.data(), nx.data(), ny.data(), fn.data(), key.data()};
  }

  // the stage's launches on `stream` (asynchronous)
  void launch();
  // the per-candidate work arrays sized for n candidates (n_cand n); the
  // layout's (node, key, start, entry) and the warm start's (prev_key,
  // prev_lambda, n_prev) are the caller's (where the whole step's GPU search
  // writes them, cuda/device_step.cu)
  void size_pairs(size_t n);
  // The colouring kept is not reused: the candidates were searched again
  // (their indices name other pairs), on `stream`.
  void forget_colouring();
};

}  // namespace engine
