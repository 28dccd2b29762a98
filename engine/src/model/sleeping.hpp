// The sleeping far field (docs/model.md §3.5): bodies at rest in equilibrium
// are held where they are and their triangles are not computed.
//
// Most of a 50 m punch-through domain barely moves, yet every triangle costs
// the same each step. What sleeps is a body, never a lone node: a node's own
// out-of-balance force holds the elastic vibration of its block (0.1-0.3 of
// its weight on the demo keel, 10 g in the tiniest elements), so a per-node
// test is never met, while the body's balance is what rest means.
//
// A body falls asleep at the end of a window of `quiet_steps` updates when
//  - every one of its free nodes was slower than `velocity` at every update
//    of the window, and
//  - its mean resultant force over the window is below `force` times its
//    weight, and its mean resultant moment about its centre below `force`
//    times its weight times its size sqrt(A). Both means are the change of
//    its momentum and angular momentum over the window, which the update
//    keeps exactly; internal forces cancel in them, and vibration faster
//    than the window averages out (for bonded blocks, which share nodes,
//    the element forces through a shared node are loads on the body that
//    does not own it). Net weight of submerged ice: ~0.1 of the weight
//    ((rho_w - rho_i)/rho_i), so 1e-3 is ~1 % of the gravity-buoyancy
//    imbalance.
// A body with a held or driven node (the layer, the indenter) is loaded
// through it and never sleeps.
// Falling asleep sets the body's velocities to zero (that kinetic energy,
// below m velocity²/2 per node, is booked as damping). The next update
// computes its triangles once more at their frozen place and keeps each
// node's total force as its reference; after that nothing of the body moves,
// its triangles are skipped and their stored corner forces are what the
// nodes gather. An asleep node is a support that holds its reference force
// and at most `force` m g more: when its total force (elements, contact,
// friction, bonds, water, weight) differs from the reference by more, it
// wakes in that same update and its whole body wakes after it; a bond point
// that splits wakes both its bodies. Contact and bond checks still see every
// triangle and bond point, so a bond point in a sleeping region cannot fail
// unseen: its stress cannot change while its triangles sleep, and a force
// that would change it wakes them.
#pragma once
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "common/mesh_arrays.hpp"

namespace engine {

// No defaults here: they are the registry's (icerubble/parameters.py).
struct SleepParams {
  bool on = false;
  double velocity = NAN;    // [m/s]
  double force = NAN;       // fraction of the weight m_phys g [-]
  int32_t quiet_steps = 0;
};

// The check of these against the registry's ranges (Model::set_parameters).
void validate(const SleepParams& p);

// An awake free node's speed after its update: counts the updates in a row
// it has been slower than the sleep velocity.
inline void count_quiet(const SleepParams& p, double vx, double vy, int32_t& quiet) {
  if (vx * vx + vy * vy < p.velocity * p.velocity) {
    if (quiet < std::numeric_limits<int32_t>::max()) ++quiet;
  } else {
    quiet = 0;
  }
}

// An asleep node whose total force moved by (dfx, dfy) from its reference
// must wake (weight: its m_phys g).
inline bool wakes(const SleepParams& p, double dfx, double dfy, double weight) {
  const double fmax = p.force * weight;
  return dfx * dfx + dfy * dfy > fmax * fmax;
}

// An asleep node before its update (sleep state 1: just fallen asleep, 2:
// held): true while it stays held (v = 0: no work, no kinetic energy). Its
// first held update keeps its force as the reference; after that it wakes
// when pushed harder than the sleep force beyond it (weight: its m_phys g)
// and moves on in this very step, and its whole body wakes after the update
// (wake_body). changes counts the nodes whose state changed.
inline bool stays_asleep(const SleepParams& p, Nodes& N, int32_t i, double weight, double& changes,
                         bool& wake_body) {
  wake_body = false;
  if (N.sleep[i] == 1) {
    N.f_ref_x[i] = N.f_x[i];
    N.f_ref_y[i] = N.f_y[i];
    N.sleep[i] = 2;
    changes += 1.0;
    return true;
  }
  if (!wakes(p, N.f_x[i] - N.f_ref_x[i], N.f_y[i] - N.f_ref_y[i], weight)) return true;
  N.sleep[i] = 0;
  N.quiet[i] = 0;
  changes += 1.0;
  wake_body = true;
  return false;
}

// The open window of the body balance check: where it started, and each
// body's momentum and angular momentum then, about the body's centre of
// weight then (kept: the moment is taken about that fixed point).
struct SleepWindow {
  int64_t start_step = -1;  // -1: none open
  double start_time = 0.0;
  int32_t n_nodes = 0;      // a split appends nodes to the bodies' node sets: reopen
  std::vector<double> cx, cy, px, py, l;
};

// Everything a resumed run needs to sleep and wake as the run it continues.
struct SleepState {
  std::vector<uint8_t> sleep;
  std::vector<int32_t> quiet;
  std::vector<double> f_ref_x, f_ref_y;
  SleepWindow window;
};

}  // namespace engine
