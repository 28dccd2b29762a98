// Energy bookkeeping (docs/model.md §4): current energies and cumulative works.
//
// Works are integrated with the midpoint rule on the central-difference
// velocities, W += dt f^n . (v^{n-1/2} + v^{n+1/2}) / 2, for which the change
// of kinetic energy (at half steps) equals the total work exactly. The
// residual is therefore only the mismatch between the elastic (and contact)
// energy and the work of those forces: second order in dt.
// All values in J per m width.
#pragma once

#include "model/step_sums.hpp"

namespace engine {

struct EnergyLedger {
  // Current values.
  double kinetic = 0.0;  // 1/2 m v² at t - dt/2 of the next step
  double elastic = 0.0;  // strain energy at the last force evaluation
  // Cumulative energy taken up by each non-conservative or contact force
  // (minus the work of that force on the nodes).
  double contact = 0.0;   // normal contact: stored energy of the overlaps
  double friction = 0.0;  // friction dissipation
  double damping = 0.0;   // strain-rate damping dissipation
  double drag = 0.0;      // water drag dissipation
  double cohesive = 0.0;  // freeze-bond cohesive forces: work minus cohesive_stored
  double cohesive_stored = 0.0;  // current, recoverable on the secant branches (freeze_bonds.cpp)
  // Cumulative work done on the system by sources.
  double work_gravity = 0.0;
  double work_buoyancy = 0.0;
  double work_boundary = 0.0;  // prescribed velocities and fixed nodes
  // The contact module's own accounts (diagnostics; not in the residual).
  double contact_solver = 0.0;
  double friction_solver = 0.0;
  // Kinetic + elastic when bookkeeping (re)started, and the elastic energy
  // moved to the same half step as the work (see Model::update_positions).
  double initial = 0.0;
  double elastic_midstep = 0.0;
  bool started = false;

  double stored() const { return kinetic + elastic_midstep + contact + cohesive_stored; }
  double dissipated() const { return friction + damping + drag + cohesive; }
  double supplied() const { return work_gravity + work_buoyancy + work_boundary; }
  // Energy present or lost minus energy brought in: 0 for an exact scheme.
  double residual() const { return stored() + dissipated() - initial - supplied(); }
  // Size of the terms, the yardstick for the residual.
  double scale() const;
  // Book one step's node sums (the update's midpoint-rule powers, kinetic
  // sums and elastic powers) over its dt; contact_now: the contact module's
  // potential energy now (a diagnostic, contact_solver).
  void book_step(const StepSums& s, double dt, double contact_now);
};

}  // namespace engine
