// The time step of docs/model.md §3: preparation, the stable-step check,
// the force stages in their one order, and the central-difference update
// with the work integration of the energy ledger.
#include "common/input_errors.hpp"
#include "model/model.hpp"

#include <omp.h>

#include <algorithm>
#include <cmath>

#include "common/stopwatch.hpp"
#include "model/reach_kernel.hpp"
#include "model/threading.hpp"

namespace engine {

// A step derived from the stable step (dt_fraction 1) is not refused when the
// step recomputed after a bond split differs from it in the last digits only
// (the split node's mass share is a quotient, its own mass a sum).
constexpr double kRoundOff = 1.0 + 1e-14;

void Model::prepare_topology() {
  if (prepared_) return;
  rebuild_topology();  // node splitting may have appended nodes or moved corners
  compute_masses();
  build_constraints();
  stable_current_ = false;
  prepared_ = true;
}

StableStep Model::stable_step() {
  require_parameters();
  prepare_topology();
  if (!stable_current_) {
    // The mesh's stable step, in its reference configuration: strains are
    // small, and it is then the same before and after bond points split
    // (per-body shares), up to round-off.
    const ContactStableStep contact =
        contact_possible_ ? contact_critical_dt(reference_contact_stiffness(), nodes_.mass.data())
                          : ContactStableStep{};
    extend_reach_origin();
    stable_ = stable_time_step(nodes_, tris_, elem_mat_, element_dt0_, contact_possible_, contact, params_.external, body_area0_);
    report_added_mass();
    stable_current_ = true;
  }
  return stable_;
}

bool Model::use_threads() const { return tris_.size() >= kMinParallelTriangles; }

int Model::thread_count() const {
  return std::min(params_.threads > 0 ? params_.threads : omp_get_max_threads(), kMaxThreads);
}

void Model::prepare() {
  stable_step();
  const int nt = thread_count();
  partial_.assign(size_t(nt), ThreadSums{});
}

// ---------------------------------------------------------------- the time step

void Model::step(int64_t n) {
  if (n < 0) bad("n (number of steps) must be >= 0");
  prepare();
  if (!(dt_ > 0.0)) bad("dt is not set: call set(dt=...) with dt > 0 s");
  if (params_.check_stable_dt && dt_ > stable_.dt * kRoundOff)
    bad("dt = " + num17(dt_) + " s exceeds the stable step " + num17(stable_.dt) + " s (by " +
        num(100.0 * (dt_ / stable_.dt - 1.0)) + " %; the stable step is recomputed when bond points split): " +
        stable_.describe(tris_.body) +
        ". Reduce dt, or coarsen the governing elements / lower the penalty.");
  for (int64_t k = 0; k < n; ++k) {
    Stopwatch total(timings_.total);
    advance();
    ++timings_.steps;
  }
}

void Model::advance() {
  compute_forces(History::commit);
  update_positions();           // (7) central difference, work integration
  if (params_.sleep.on) update_sleep();  // bodies woken, bodies at rest put to sleep
  guard_stability();
  if (contact_possible_ && std::isfinite(params_.contact_reach) && step_count_ % kReachCheckEvery == 0)
    guard_contact_reach();
}

// The contact step bound with a finite reach holds while no node has moved
// more than reach/2 since it was taken (two nodes closing in from both sides
// close the gap by reach). Checked every kReachCheckEvery steps: a node moves
// far less than a millimetre in that time.
// Where the reach guard measures a node's move from: a node split off since
// the step was last bound starts from its reference place (an earlier
// re-check at most).
void Model::extend_reach_origin() {
  for (size_t i = reach_x_.size(); i < size_t(nodes_.size()); ++i) {
    reach_x_.push_back(nodes_.x0[i]);
    reach_y_.push_back(nodes_.y0[i]);
  }
}

void Model::guard_contact_reach() {
  const double half = 0.5 * params_.contact_reach;
  extend_reach_origin();  // points split since the step began (step(n) prepares once)
  bool moved = false;
  for (int32_t i = 0; i < nodes_.size() && !moved; ++i)
    moved = moved_past_reach(nodes_.x[i], nodes_.y[i], reach_x_[i], reach_y_[i], half);  // model/reach_kernel.hpp
  if (!moved) return;
  // the stiffness of the current configuration, for the step and any raise
  const ContactStiffness now = contact_stiffness(params_.contact, contact_input(), params_.contact_reach);
  const ContactStableStep c = contact_critical_dt(now, nodes_.mass.data());
  reach_x_ = nodes_.x;
  reach_y_ = nodes_.y;
  const double limit = kTimeStepSafety * c.dt;
  if (params_.check_stable_dt && dt_ > limit * kRoundOff && params_.mass_scaling_dt > 0.0) {
    raise_contact_masses(now);  // mass scaling is allowed: scale the nodes that now need it
    return;
  }
  if (params_.check_stable_dt && dt_ > limit * kRoundOff)
    throw InstabilityError(
        "at step " + std::to_string(step_count_) + " (t = " + num(time_) + " s) the blocks have moved " +
        "within contact reach of stiffer boundaries: dt = " + num17(dt_) + " s now exceeds the contact " +
        "stable step " + num17(limit) + " s (by " + num(100.0 * (dt_ / limit - 1.0)) + " %; 0.9 x the limit " +
        "of surface node " + std::to_string(c.node) + ", mass " + num(c.mass) + " kg/m, at (" +
        num(nodes_.x[c.node]) + ", " + num(nodes_.y[c.node]) + ") m). Use a larger contact_reach (the step " +
        "then holds for every boundary within reach at the start) or a smaller dt / larger mass_scaling_dt.");
}

void Model::evaluate() {
  prepare();
  compute_forces(History::leave);
}

void Model::evaluate_before_cohesive() {
  prepare();
  compute_body_forces();
  compute_contact_forces();
}

// The one order of the force stages. Only a committed step may split bond
// points or move the cohesive pairs' history on: evaluate() looks at the
// forces of the current state and leaves it as it was.
void Model::compute_forces(History history) {
  // (1) element internal forces and (6) gravity, buoyancy, drag: both depend
  // only on the state at t, so one pass computes them (half the thread
  // synchronisations of two passes).
  compute_body_forces();
  compute_contact_forces();     // (2) neighbour search, (3) normal contact forces
  if (history == History::commit)  // (4) bond stress check (eqs 5-7), then node splitting
    apply_topology_changes(check_freeze_bonds());
  apply_cohesive_forces(history);  // (5) cohesive forces of opened bonds (eqs 8-12)
  assemble_forces();            // total of (1)-(6)
  apply_friction(history);      // (3b) Coulomb friction (eq 4), needs all forces above
  apply_boundary_conditions();  // fixed nodes, prescribed velocities, reactions
}

UpdateArrays Model::update_arrays(double dt, double g, double alpha) {
  Nodes& N = nodes_;
  return {N.x.data(),       N.y.data(),       N.vx.data(),       N.vy.data(),      N.mass.data(),
          N.mass_phys.data(), N.f_x.data(),   N.f_y.data(),      N.f_pre_x.data(), N.f_pre_y.data(),
          N.f_int_x.data(), N.f_int_y.data(), N.f_visc_x.data(), N.f_visc_y.data(), N.f_con_x.data(),
          N.f_con_y.data(), N.f_coh_x.data(), N.f_coh_y.data(), N.f_buoy_y.data(), N.drag_k.data(),
          N.r_x.data(),     N.r_y.data(),     N.v_bc_x.data(),   N.v_bc_y.data(),  N.constrained.data(),
          dt,               g,                alpha};
}

void Model::update_positions() {
  Stopwatch sw(timings_.integration);
  const int nt = int(partial_.size());
  const int32_t n = nodes_.size();
  const double dt = dt_;
  const double g = params_.external.gravity ? params_.external.g : 0.0;
  const double alpha = params_.local_damping;
  const bool sleeping = params_.sleep.on;
  const SleepParams sp = params_.sleep;
  // the sleep force is a fraction of the weight at the set g, also with gravity off
  const double g_sleep = params_.external.g;
  if (sleeping && body_wake_.size() != size_t(n_bodies())) body_wake_.assign(size_t(n_bodies()), 0);
  uint8_t* body_wake = body_wake_.data();
  const int32_t* node_body = node_body_.data();
  const UpdateArrays u = update_arrays(dt, g, alpha);
  #pragma omp parallel num_threads(nt) if (use_threads())
  {
    Nodes& N = nodes_;
    // Plain local accumulators, stored once at the end: summing straight into
    // the struct's members compiles to other (fused) operations and changes
    // the last bits of the energies against earlier runs.
    double kinetic2_new = 0.0, kinetic2_old = 0.0, viscous = 0.0, local_damping = 0.0;
    double contact = 0.0, friction = 0.0, cohesive = 0.0, gravity = 0.0, buoyancy = 0.0;
    double drag = 0.0, boundary = 0.0, elastic_new = 0.0, elastic_old = 0.0;
    double sleep_changes = 0.0;
    #pragma omp for schedule(static)
    for (int32_t i = 0; i < n; ++i) {
      if (sleeping && N.sleep[i]) {  // sleeping.hpp
        bool wake_body;
        if (stays_asleep(sp, N, i, N.mass_phys[i] * g_sleep, sleep_changes, wake_body)) continue;
        if (wake_body) {
          #pragma omp atomic write
          body_wake[node_body[i]] = uint8_t(1);
        }
      }
      const NodeWork w = update_node(u, i);
      if (sleeping && !N.constrained[i]) count_quiet(sp, N.vx[i], N.vy[i], N.quiet[i]);
      kinetic2_new += w.kinetic2_new;
      kinetic2_old += w.kinetic2_old;
      viscous += w.viscous;
      local_damping += w.local_damping;
      contact += w.contact;
      friction += w.friction;
      cohesive += w.cohesive;
      gravity -= w.gravity;
      buoyancy += w.buoyancy;
      drag -= w.drag;
      boundary += w.boundary;
      elastic_new += w.elastic_new;
      elastic_old += w.elastic_old;
    }
    StepSums& p = partial_[omp_get_thread_num()].s;
    p.sleep_changes = sleep_changes;
    p.kinetic2_new = kinetic2_new;
    p.kinetic2_old = kinetic2_old;
    p.viscous = viscous;
    p.local_damping = local_damping;
    p.contact = contact;
    p.friction = friction;
    p.cohesive = cohesive;
    p.gravity = gravity;
    p.buoyancy = buoyancy;
    p.drag = drag;
    p.boundary = boundary;
    p.elastic_new = elastic_new;
    p.elastic_old = elastic_old;
  }
  StepSums s;
  for (int t = 0; t < nt; ++t) {
    s += partial_[t].s;
    partial_[t].s = StepSums{};
  }
  energy_.book_step(s, dt, contact_work_step_);  // energy.cpp
  if (s.sleep_changes > 0.0) awake_current_ = false;
  time_ += dt;
  ++step_count_;
}

}  // namespace engine
