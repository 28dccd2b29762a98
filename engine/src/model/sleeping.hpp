// The sleeping far field (docs/model.md §3.5): nodes at rest in equilibrium
// are held where they are and the triangles among them are not computed.
//
// Most of a 50 m punch-through domain barely moves, yet every triangle costs
// the same each step. A free node falls asleep after `quiet_steps` updates
// in a row with speed below `velocity` and out-of-balance force below
// `force` times its weight m g (the net weight of submerged ice is 0.089 m g:
// 1e-3 is about 1 % of the gravity-buoyancy imbalance that settles rubble);
// its velocity is then set to zero (that kinetic energy, below
// m velocity²/2, is booked as damping). An asleep node does not move: it is
// a support that can push back with at most `force` m g. It wakes, in the
// same step, as soon as its total force (elements, contact, friction, bonds,
// water, weight) exceeds that, or when a bond point at it splits; a node with
// a boundary condition never sleeps.
// A triangle is computed while any of its corners is awake or fell asleep at
// the last update, so it is computed once more at its frozen place with zero
// velocities; after that its corner forces, stress and strain energy stay
// exactly what they are (nothing of it moves), and they are what the nodes
// gather. Contact and bond checks still see every triangle and bond point, so
// a bond point in a sleeping region cannot fail unseen: its stress cannot
// change while its triangles sleep, and a force that would change it wakes them.
#pragma once
#include <cmath>
#include <cstdint>

namespace engine {

struct SleepParams {
  bool on = false;
  double velocity = 1e-4;   // [m/s]
  double force = 1e-3;      // fraction of the node's weight m_phys g [-]
  int32_t quiet_steps = 100;
};

// A node's state after its update: sleep and quiet are Nodes::sleep and
// Nodes::quiet, v its new velocity, f its total force of the step, weight
// its m_phys g. Returns true when the node fell asleep (set v to zero).
inline bool falls_asleep(const SleepParams& p, double vx, double vy, double fx, double fy,
                         double weight, int32_t& quiet) {
  const double fmax = p.force * weight;
  if (vx * vx + vy * vy < p.velocity * p.velocity && fx * fx + fy * fy < fmax * fmax) {
    if (++quiet >= p.quiet_steps) {
      quiet = 0;
      return true;
    }
  } else {
    quiet = 0;
  }
  return false;
}

// An asleep node with total force (fx, fy) and weight m_phys g must wake.
inline bool wakes(const SleepParams& p, double fx, double fy, double weight) {
  const double fmax = p.force * weight;
  return fx * fx + fy * fy > fmax * fmax;
}

}  // namespace engine
