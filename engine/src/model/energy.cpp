#include "model/energy.hpp"

#include <cmath>

namespace engine {

double EnergyLedger::scale() const {
  return std::fabs(kinetic) + std::fabs(elastic_midstep) + std::fabs(contact) +
         std::fabs(friction) + std::fabs(damping) + std::fabs(drag) + std::fabs(cohesive) + std::fabs(cohesive_stored) +
         std::fabs(work_gravity) + std::fabs(work_buoyancy) + std::fabs(work_boundary) +
         std::fabs(initial);
}

void EnergyLedger::book_step(const StepSums& s, double dt, double contact_now) {
  if (!started) {
    // Bookkeeping starts at x^{-1/2} = x^0 - dt v^{-1/2}/2, where the
    // midpoint-rule work starts: move U^0 there to first order.
    initial = 0.5 * s.kinetic2_old + elastic + 0.5 * dt * s.elastic_old;
    started = true;
  }
  kinetic = 0.5 * s.kinetic2_new;
  damping -= dt * (s.viscous + s.local_damping);
  contact -= dt * s.contact;
  friction -= dt * s.friction;
  cohesive -= dt * s.cohesive;
  work_gravity += dt * s.gravity;
  work_buoyancy += dt * s.buoyancy;
  drag -= dt * s.drag;
  work_boundary += dt * s.boundary;
  // The works cover the motion up to x^{n+1/2}; so must the elastic energy.
  elastic_midstep = elastic - 0.5 * dt * s.elastic_new;
  contact_solver = contact_now;
}

}  // namespace engine
