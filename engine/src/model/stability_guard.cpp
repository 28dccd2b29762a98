// The runtime stability guard: non-finite values, inverted elements and
// energy growing without a source stop the run with InstabilityError.
#include "common/input_errors.hpp"
#include "model/model.hpp"

#include <cmath>
#include <sstream>

#include "common/stopwatch.hpp"
#include "element/cst_element.hpp"

namespace engine {

namespace {

// How far the plain stored energy may exceed the energy flows (see guard_stability).
constexpr double kGrowthFactor = 10.0;

}  // namespace

void Model::fail(const std::string& what, int32_t node, int32_t tri) const {
  std::ostringstream o;
  o.precision(6);
  o << "run stopped at step " << step_count_ << " (t = " << time_ << " s): " << what;
  if (node >= 0)
    o << "; at node " << node << " of body " << body_of_node(node) << ", position ("
      << nodes_.x[node] << ", " << nodes_.y[node] << ") m, initially (" << nodes_.x0[node]
      << ", " << nodes_.y0[node] << ") m";
  if (tri >= 0) {
    const int32_t* c = &tris_.node[3 * tri];
    o << "; at triangle " << tri << " of body " << tris_.body[tri] << ", centroid ("
      << (nodes_.x[c[0]] + nodes_.x[c[1]] + nodes_.x[c[2]]) / 3.0 << ", "
      << (nodes_.y[c[0]] + nodes_.y[c[1]] + nodes_.y[c[2]]) / 3.0 << ") m";
  }
  o << ". dt = " << dt_ << " s, stable estimate " << stable_.dt << " s.";
  throw InstabilityError(o.str());
}

EnergyAlarm Model::energy_alarm(const EnergyLedger& E) const {
  EnergyAlarm a;
  a.residual = E.residual();
  a.scale = E.scale();
  a.flows = std::fabs(E.initial) + std::fabs(E.work_gravity) + std::fabs(E.work_buoyancy) +
            std::fabs(E.work_boundary) + std::fabs(E.dissipated());
  a.excess = E.kinetic + E.elastic + E.contact + E.dissipated() - E.initial - E.supplied();
  a.growth = a.excess > kGrowthFactor * a.flows;
  a.imbalance = a.residual > params_.energy_tolerance * a.scale && a.scale > 0.0;
  return a;
}

void Model::guard_stability() {
  Stopwatch sw(timings_.integration);
  const EnergyLedger& E = energy_;
  const int32_t n = nodes_.size();
  if (!std::isfinite(E.kinetic) || !std::isfinite(E.elastic) || !std::isfinite(E.residual())) {
    const char* which = !std::isfinite(E.kinetic) ? "kinetic" : !std::isfinite(E.elastic) ? "elastic" : "contact/work";
    for (int32_t i = 0; i < n; ++i) {
      const Nodes& N = nodes_;
      if (!std::isfinite(N.x[i]) || !std::isfinite(N.y[i]) || !std::isfinite(N.vx[i]) ||
          !std::isfinite(N.vy[i]) || !std::isfinite(N.f_x[i]) || !std::isfinite(N.f_y[i])) {
        const char* what = !std::isfinite(N.f_con_x[i]) || !std::isfinite(N.f_con_y[i])
                               ? "contact force"
                           : !std::isfinite(N.f_int_x[i]) || !std::isfinite(N.f_int_y[i])
                               ? "internal force"
                               : "force/velocity";
        fail(std::string("non-finite ") + what + " (" + which + " energy not finite)", i, -1);
      }
    }
    fail(std::string("non-finite ") + which + " energy", -1, -1);
  }
  // Two energy checks. (a) The balance residual (stored energy moved to the
  // half step, as the works are): sensitive (O(dt²) in a sound run), catches
  // energy made by a force, e.g. a non-conservative contact. (b) The plain
  // stored energy KE + U + contact against what the sources supplied: the
  // central difference conserves a shadow energy even when unstable, so (a)
  // is blind to a time-step instability, while (b) sees it grow. In a stable
  // run the plain energy of a mode can exceed the shadow energy by
  // 1/(1 - (w dt/2)²), 5x at 0.9 of the critical step (and a start from rest
  // in that mode reaches it), so (b) fires above kGrowthFactor = 10x the
  // energy flows; an unstable mode grows 5-20x per step and is caught within
  // a step or two.
  const EnergyAlarm alarm = energy_alarm(E);
  if (params_.check_energy && alarm.fires()) {
    const bool growth = alarm.growth;
    const double excess = alarm.excess, flows = alarm.flows, residual = alarm.residual, scale = alarm.scale;
    // Where: the node with the most kinetic energy, the triangle with the
    // highest strain energy density.
    int32_t node = 0, tri = 0;
    double kmax = -1.0, umax = -1.0;
    for (int32_t i = 0; i < n; ++i) {
      const double k = nodes_.mass[i] * (nodes_.vx[i] * nodes_.vx[i] + nodes_.vy[i] * nodes_.vy[i]);
      if (k > kmax) { kmax = k; node = i; }
    }
    for (int32_t t = 0; t < tris_.size(); ++t) {
      const double u = element_strain_energy(nodes_, tris_, elem_mat_, t) / tris_.area0[t];
      if (u > umax) { umax = u; tri = t; }
    }
    const char* which = E.kinetic >= E.elastic && E.kinetic >= E.contact ? "kinetic"
                        : E.elastic >= E.contact ? "elastic" : "contact";
    const std::string test =
        growth ? "stored energy exceeds the energy supplied by " + num(excess) +
                     " J/m, more than 10 x all energy flows so far (" + num(flows) + " J/m)"
               : "balance residual " + num(residual) + " J/m > energy_tolerance " +
                     num(params_.energy_tolerance) + " x " + num(scale) + " J/m";
    fail(std::string(which) + " energy grew without an energy source: kinetic " + num(E.kinetic) +
             ", elastic " + num(E.elastic) + ", contact " + num(E.contact) + " J/m; " + test +
             "; largest kinetic energy at the node, largest strain energy density in the triangle below",
         node, tri);
  }
  if (first_inverted_ >= 0)
    fail("element inverted (det F <= 0): the mesh has collapsed, usually a too large dt or penalty overlap",
         -1, first_inverted_);
}

}  // namespace engine
