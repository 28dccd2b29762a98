// Cohesive crack growth of one opened bond point (Polojärvi & Tuhkuri 2013, eqs 8-12):
// linear softening of the cohesive force with the effective opening, secant
// unloading/reloading, irreversibility and full failure.
//
// Sign convention. delta = x+ - x- is the opening (x+ and x- the two nodes made by the
// split), n the bond surface normal pointing from the - side to the + side, and
// t = (-n_y, n_x) the tangent; delta_n = delta.n, delta_t = delta.t. The law returns the
// cohesive force f = (f_n, f_t) as written in eq 11, i.e. pointing along the opening;
// it is applied as  f_on_plus = -f,  f_on_minus = +f  (so f+ = -f-, and the pair pulls
// the crack faces together). See nodal_forces().
//
// State of an opened bond point: f0 (|f_c^0| of eq 8, or the effective value for the
// work-conjugate direction, see initial_effective_force), delta_f (eq 12) and
// delta_m, the largest effective opening so far. The bond point is fully broken once
// delta_m >= delta_f; after that the force is zero for ever, whatever the opening does.
#pragma once

#include <cmath>
#include <cstdint>

#include "cohesive_law/host_device.hpp"

namespace cohesive_law {

// How the scalar |f_c| of eq 10 is turned into force components.
//   paper:          eq 11 as printed, f_t = |f_c| beta delta_t/delta_e, f_n = |f_c| <delta_n>/delta_e.
//                   |f| = |f_c|; the work over a full opening is G l in pure tension
//                   but G l / beta in pure shear (docs/model.md §3.3 energy caveat).
//   work_conjugate: Ortiz & Pandolfi (1999), f_t = |f_c| beta^2 delta_t/delta_e: f is the
//                   gradient of the effective opening scaled by |f_c|, so
//                   f . d(delta) = |f_c| d(delta_e) and the work is G l on every path.
enum class ForceDirection : int { paper = 0, work_conjugate = 1 };

// Failure mode codes, as stored in result files (docs/results_format.md, /bonds/mode).
enum class FailureMode : std::int8_t { none = 0, tensile = 1, shear = 2 };

COHESIVE_LAW_HD double macaulay(double x) { return x > 0.0 ? x : 0.0; }

// Eq 9. A closed crack (delta_n < 0) contributes no normal opening: its faces touch
// through the ordinary contact, which is independent of the cohesive law.
COHESIVE_LAW_HD double effective_opening(double delta_n, double delta_t, double beta) {
  const double dn = macaulay(delta_n);
  return sqrt(beta * beta * delta_t * delta_t + dn * dn);
}

// Eq 8: |f_c^0| = |-(m-/m) f+ + (m+/m) f-| with f+- the internal force vectors of the
// elements on each side at the split (components x, y). Keeps both new nodes'
// accelerations equal to the old node's at the instant of splitting.
COHESIVE_LAW_HD double initial_force_magnitude(double m_plus, double m_minus, double f_plus_x,
                                      double f_plus_y, double f_minus_x, double f_minus_y) {
  const double m = m_plus + m_minus;
  const double gx = (-m_minus * f_plus_x + m_plus * f_minus_x) / m;
  const double gy = (-m_minus * f_plus_y + m_plus * f_minus_y) / m;
  return hypot(gx, gy);
}

// The scalar that multiplies the direction of eq 11, from the eq-8 force vector
// written in bond axes (f_n, f_t). For the paper's direction it is |f| (eq 8). For the
// work-conjugate direction the force is |f_c| (beta^2 delta_t, <delta_n>)/delta_e, whose
// length is not |f_c|; the matching scalar is the effective force
// sqrt(f_n^2 + f_t^2/beta^2), so the first cohesive force equals the split force in
// pure tension and pure shear (at tau_cr l, not beta tau_cr l).
COHESIVE_LAW_HD double initial_effective_force(double f_n, double f_t, double beta, ForceDirection dir) {
  // sqrt of the sum, not hypot: CUDA's hypot and the C library's differ in the
  // last bits, products and sqrt are IEEE on both (no fused multiply-add), so
  // the GPU's rigid-phase force is the CPU's bit for bit (docs/gpu.md)
  if (dir == ForceDirection::paper) return sqrt(f_n * f_n + f_t * f_t);
  return sqrt(f_n * f_n + f_t * f_t / (beta * beta));
}

// Eq 12: delta_f = 2 G l / |f_c^0|, so that the area under eq 10 is G l.
COHESIVE_LAW_HD double critical_opening(double G, double l, double f0) { return 2.0 * G * l / f0; }

// Eq 10 for delta_m already updated (delta_m >= delta_e): on the softening line while
// loading, on the secant to the origin while un-/reloading below delta_m.
COHESIVE_LAW_HD double softening_force(double delta_e, double delta_m, double delta_f, double f0) {
  if (delta_m >= delta_f) return 0.0;
  if (delta_e >= delta_m) return f0 * (1.0 - delta_e / delta_f);
  return f0 * (1.0 - delta_m / delta_f) * delta_e / delta_m;
}

// Eq 11 (paper) or its work-conjugate form. Zero at delta_e = 0 (closed crack, no
// direction defined; the contact of the faces takes over).
COHESIVE_LAW_HD void force_components(double F, double delta_n, double delta_t, double delta_e,
                             double beta, ForceDirection dir, double& f_n, double& f_t) {
  if (delta_e <= 0.0 || F == 0.0) {
    f_n = 0.0;
    f_t = 0.0;
    return;
  }
  const double s = F / delta_e;
  f_n = s * macaulay(delta_n);
  f_t = s * (dir == ForceDirection::paper ? beta : beta * beta) * delta_t;
}

// Full failure classification (docs/model.md §3.3): tensile if delta_n >= |delta_t|.
COHESIVE_LAW_HD FailureMode failure_mode(double delta_n, double delta_t) {
  return delta_n >= fabs(delta_t) ? FailureMode::tensile : FailureMode::shear;
}

// Energy dissipated by the law (in the effective measure, the quantity eq 12 sets to
// G l) when delta_m grows from delta_m_old to delta_m_new: the area between the
// softening line and the secants, 1/2 f0 (delta_m_new - delta_m_old). Exact, not a
// quadrature. For the work-conjugate direction it is also the mechanical dissipation;
// for the paper's direction the mechanical work differs (see work_increment).
COHESIVE_LAW_HD double dissipation_increment(double f0, double delta_f, double delta_m_old,
                                    double delta_m_new) {
  const double a = delta_m_old < delta_f ? delta_m_old : delta_f;
  const double b = delta_m_new < delta_f ? delta_m_new : delta_f;
  return b > a ? 0.5 * f0 * (b - a) : 0.0;
}

// Mechanical work done against the cohesive force over one step, trapezoid rule:
// 1/2 (f_old + f_new) . (delta_new - delta_old). This is what an energy balance of the
// engine must count (it is the work of the forces the nodes actually feel); it is exact
// for steps on which the force is linear in the opening components.
COHESIVE_LAW_HD double work_increment(double f_n_old, double f_t_old, double f_n_new, double f_t_new,
                             double d_delta_n, double d_delta_t) {
  return 0.5 * ((f_n_old + f_n_new) * d_delta_n + (f_t_old + f_t_new) * d_delta_t);
}

// Energy stored in an opened bond point and given back if it closes along the secant
// (eq 10, un-/reloading branch, slope k_s = |f_c|(delta_m)/delta_m). The secant force is
// conservative for both directions: k_s (beta delta_t, <delta_n>) derives from
// 1/2 k_s (beta delta_t^2 + <delta_n>^2) (paper), k_s (beta^2 delta_t, <delta_n>) from
// 1/2 k_s delta_e^2 (work-conjugate). So cumulative work_increment - stored_energy is the
// mechanical dissipation of a bond point for either direction. Zero before any opening
// and after full failure.
COHESIVE_LAW_HD double stored_energy(double delta_n, double delta_t, double beta, double f0,
                            double delta_f, double delta_m, ForceDirection dir) {
  if (delta_m <= 0.0 || delta_m >= delta_f) return 0.0;
  const double ks = f0 * (1.0 - delta_m / delta_f) / delta_m;
  const double dn = macaulay(delta_n);
  const double c = dir == ForceDirection::paper ? beta : beta * beta;
  return 0.5 * ks * (c * delta_t * delta_t + dn * dn);
}

// Result of one step of one bond point.
struct StepOutcome {
  double f_n = 0.0, f_t = 0.0;  // cohesive force at the end of the step (eq 11)
  double dissipation = 0.0;     // dissipation_increment of the step
  bool failed_now = false;      // full failure happened in this step
  FailureMode mode = FailureMode::none;  // set when failed_now
};

// One step of an opened bond point to the opening (delta_n, delta_t) at the end of the
// step. Updates delta_m in place (it is the only history variable). Straight-line
// steps: delta_e is convex along a straight segment, so its maximum over the step is at
// an end point and max(delta_m, delta_e_new) is the exact new delta_m.
COHESIVE_LAW_HD StepOutcome step_opened_bond(double delta_n, double delta_t, double beta, double f0,
                                    double delta_f, double& delta_m, ForceDirection dir) {
  StepOutcome out;
  if (delta_m >= delta_f) return out;  // broken: irreversible, no force
  const double de = effective_opening(delta_n, delta_t, beta);
  const double dm_old = delta_m;
  if (de > delta_m) delta_m = de;
  out.dissipation = dissipation_increment(f0, delta_f, dm_old, delta_m);
  if (delta_m >= delta_f) {
    out.failed_now = true;
    out.mode = failure_mode(delta_n, delta_t);
    return out;
  }
  force_components(softening_force(de, delta_m, delta_f, f0), delta_n, delta_t, de, beta, dir,
                   out.f_n, out.f_t);
  return out;
}

// Opening components in bond axes from the nodal separation x+ - x- and the normal n
// (unit, pointing from the - side to the + side).
COHESIVE_LAW_HD void opening_components(double dx, double dy, double n_x, double n_y, double& delta_n,
                               double& delta_t) {
  delta_n = dx * n_x + dy * n_y;
  delta_t = -dx * n_y + dy * n_x;
}

// Nodal forces from the law's (f_n, f_t): f_plus = -f, f_minus = +f (momentum conserved,
// the pair resists the opening).
COHESIVE_LAW_HD void nodal_forces(double f_n, double f_t, double n_x, double n_y, double& f_plus_x,
                         double& f_plus_y, double& f_minus_x, double& f_minus_y) {
  const double fx = f_n * n_x - f_t * n_y;
  const double fy = f_n * n_y + f_t * n_x;
  f_plus_x = -fx;
  f_plus_y = -fy;
  f_minus_x = fx;
  f_minus_y = fy;
}

}  // namespace cohesive_law
