// Freeze bonds between rigid blocks (the discrete-only model, docs/model.md §6).
//
// A bond point joins two blocks a and b at a point of their common face: it is
// anchored in each block's body frame (the same world point when the bond is
// made) and has the face's unit normal, fixed in a's frame (it turns with a).
// The opening is the separation of the two anchors, split along the normal
// (delta_n) and the tangent t = z x n (delta_t). Rigid blocks have no elements
// to carry an intact bond's traction, so the bond follows the initially-elastic
// variant of the cohesive law (cohesive_law/elastic_bond.hpp): a spring k up to
// the criterion of eqs 5-6, then the linear softening of eqs 8-12 with the same
// G, failing at delta_f. Per bond point: its crack length l, strength sigma_cr,
// tau_cr (graded with depth by the caller), mu and G.
//
// Forces: b gets -(f_n n + f_t t), a the opposite, both at the midpoint of the
// two anchors (no spurious couple);
// per-body sums in bond point order. Per metre of width.
#pragma once
#include <cstdint>
#include <vector>

#include "cohesive_law/elastic_bond.hpp"

namespace engine {

struct RigidBondPoints {
  // the bond points (set once)
  std::vector<int32_t> a, b;
  std::vector<double> ax, ay, bx, by;  // anchors in a's and b's body frames [m]
  std::vector<double> nx, ny;          // unit normal in a's body frame, pointing from a to b
  std::vector<double> k, l, sigma_cr, tau_cr, mu, G;
  cohesive_law::ForceDirection direction = cohesive_law::ForceDirection::paper;
  // false: intact points stay intact (elastic) whatever their traction, as the
  // FEM-DEM holds its bonds while the scene settles
  bool failure = true;
  bool failure_last_step = true;  // to tell the step that switches failure on
  // history
  std::vector<int8_t> state;           // cohesive_law::BondState
  std::vector<double> f0, delta_f, delta_m, dn_prev, dt_prev;
  std::vector<double> dissipated;      // [J/m]
  std::vector<double> t_initiated, t_failed;  // NaN until it happens [s]
  std::vector<int8_t> mode;            // cohesive_law::FailureMode at failure
  // last step
  std::vector<double> f_n, f_t;        // [N/m]

  int32_t size() const { return int32_t(a.size()); }
  // Checks and sizes the history; throws std::invalid_argument naming the bad entry.
  void validate_and_reset(int32_t n_bodies);
  // One step to body poses (x, y, theta), at time `time` (for the events):
  // per-body force and torque about the centroid into fx, fy, tz (n_bodies).
  void step(int32_t n_bodies, const double* x, const double* y, const double* theta, double time,
            double* fx, double* fy, double* tz);
  // Elastic energy of the intact points plus that stored on the opened points' secants [J/m].
  double stored_energy() const;
};

}  // namespace engine
