// Coulomb friction with stick between rigid blocks, one history per contact
// (the discrete-only model, docs/model.md §6).
//
// YADE's polyhedra law keeps its shear force in one variable shared by all
// contacts (docs/yade_notes.md), so two blocks pushed opposite ways on a floor
// both slide. Here each contact, keyed by its body pair, carries its own
// tangential force f_t: it grows elastically with the tangential slip at the
// contact point, f_t <- f_t - k_t (v_rel . t) dt, and is capped at mu f_n
// (sliding). So below the friction limit a block rests, held by f_t within
// f/k_t of where it stuck; at the limit it slides with f_t = mu f_n against
// the slip. A contact absent from a step forgets its history. A body pair
// made to stick (phase 1's hold stage: the face contacts the mesher will bond,
// yade_scripts/make_pile.py) has no cap: it holds at any tangential force.
//
// Conventions: the normal n points from body a to body b, t = z x n; f_n >= 0
// is the normal force magnitude; f_t is the tangential force on b along t
// (a gets the opposite). Per metre of width.
#pragma once
#include <cstdint>
#include <vector>

namespace engine {

struct RigidContacts {
  int32_t n = 0;
  const int32_t* a = nullptr;  // body ids, a < b
  const int32_t* b = nullptr;
  const double* px = nullptr;  // contact point [m]
  const double* py = nullptr;
  const double* nx = nullptr;  // unit normal, a -> b
  const double* ny = nullptr;
  const double* fn = nullptr;  // normal force magnitude [N/m], >= 0
};

struct RigidBodies {
  int32_t n = 0;
  const double* x = nullptr;  // centroid [m]
  const double* y = nullptr;
  const double* vx = nullptr;  // centroid velocity [m/s]
  const double* vy = nullptr;
  const double* omega = nullptr;  // [rad/s]
};

// A body pair's key in the history (a < b): ascending keys order pairs by a, then b.
inline uint64_t friction_key(int32_t a, int32_t b) { return (uint64_t(uint32_t(a)) << 32) | uint32_t(b); }

// The friction history: tangential force per body pair, keys ascending; and
// the pairs that stick at any force (kept whether in contact or not).
struct FrictionHistory {
  std::vector<uint64_t> key;  // friction_key(a, b)
  std::vector<double> ft;
  std::vector<uint64_t> stuck;  // ascending, the same keys
};

// The tangential force of every contact this step (ft, in the contacts'
// order), the history afterwards (this step's contacts only) and each body's
// resulting force and torque about its centroid (fx, fy, tz: n_bodies each,
// summed in ascending key order, so independent of the contacts' order).
void rigid_friction(const RigidContacts& c, const RigidBodies& bodies, double dt, double k_t,
                    double mu, FrictionHistory& history, double* ft, double* fx, double* fy,
                    double* tz);

}  // namespace engine
