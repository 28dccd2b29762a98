// Initially elastic freeze bond, for the rigid-block model (docs/model.md §6): rigid blocks
// have no elements to carry the traction of an intact bond, so the bond itself is a
// spring until the criterion of eqs 5-6 is reached, then it follows the same linear
// softening as the initially rigid law, with the same G.
//
// The law lives in the same effective force - effective opening diagram as eq 10
// (Fig. 4 with a rising branch), with one stiffness k [N/m per unit width, i.e. Pa]:
//   intact:    F = k delta_e, applied with the chosen direction (eq 11 or work-conjugate);
//              equivalently f_n = k delta_n (both signs: an intact bond is glued and also
//              carries compression) and f_t = k_t delta_t with k_t = beta k (paper) or
//              beta^2 k (work-conjugate). k_t is not free: only this ratio keeps the force
//              vector continuous at the peak in every mode.
//   peak:      where t_e(f / l) = sigma_cr (eq 5), located inside the step by bisection,
//              at effective opening delta_0 and effective force F_p = k delta_0.
//   softening: the straight line from (delta_0, F_p) to (delta_f, 0), with
//              delta_f = 2 G l / F_p (eq 12 unchanged), so the whole triangle under
//              the loading path has area 1/2 F_p delta_f = G l: the elastic energy stored
//              at the peak is part of G l and is released into the crack, none comes back.
//   un-/reloading: secant to the origin (eq 10); before the peak that is the elastic
//              line itself, and just after it the secant slope is still k.
// Requirement: delta_0 < delta_f, i.e. the elastic energy at peak 1/2 F_p^2/k < G l,
// i.e. k > F_p^2 / (2 G l). min_elastic_stiffness() gives the bound for every peak on the
// tensile side; under compression F_p grows with mu |t_n| and the check is repeated at
// the peak (stiffness_error).
// After the peak the opened bond is exactly an opened bond of softening.hpp with the
// intercept f0 = F_p delta_f/(delta_f - delta_0) and delta_m = delta_0 at the start, so
// the dissipation 1/2 f0 (delta_m - delta_0) is 0 at the peak and G l at full failure.
#pragma once

#include <cstdint>

#include "cohesive_law/criterion.hpp"
#include "cohesive_law/softening.hpp"

namespace cohesive_law {

enum class BondState : std::int8_t { intact = 0, opening = 1, broken = 2 };

struct ElasticBondParams {
  double k;         // normal stiffness of the bond point [N/m per unit width = Pa]
  double l;         // crack length belonging to the bond point [m]
  double sigma_cr;  // tensile strength [Pa]
  double tau_cr;    // shear strength [Pa]
  double mu;        // friction coefficient of the closed crack [-]
  double G;         // fracture energy [J/m^2]
};

inline double tangential_stiffness(double k, double beta, ForceDirection dir) {
  return dir == ForceDirection::paper ? k * beta : k * beta * beta;
}

inline void intact_force(double delta_n, double delta_t, double k, double beta,
                         ForceDirection dir, double& f_n, double& f_t) {
  f_n = k * delta_n;
  f_t = tangential_stiffness(k, beta, dir) * delta_t;
}

inline double intact_effective_traction(double delta_n, double delta_t,
                                        const ElasticBondParams& p, ForceDirection dir) {
  const double beta = p.tau_cr / p.sigma_cr;
  double f_n, f_t;
  intact_force(delta_n, delta_t, p.k, beta, dir, f_n, f_t);
  return effective_traction(f_n / p.l, f_t / p.l, beta, p.mu);
}

// Elastic energy of an intact bond point, 1/2 (k delta_n^2 + k_t delta_t^2) (compression too).
inline double intact_stored_energy(double delta_n, double delta_t, double k, double beta,
                                   ForceDirection dir) {
  return 0.5 * (k * delta_n * delta_n + tangential_stiffness(k, beta, dir) * delta_t * delta_t);
}

// Largest effective peak force on the tensile side (t_n >= 0): max(1, beta) sigma_cr l for
// the paper's direction (|f| = F there and pure shear peaks at tau_cr l), sigma_cr l for the
// work-conjugate one (t_e = k delta_e / l there). Stiffness below F_p^2/(2 G l) would put
// the peak at or beyond delta_f.
inline double min_elastic_stiffness(double sigma_cr, double tau_cr, double G, double l,
                                    ForceDirection dir) {
  const double beta = tau_cr / sigma_cr;
  const double c = (dir == ForceDirection::paper && beta > 1.0) ? beta : 1.0;
  const double Fp = c * sigma_cr * l;
  return Fp * Fp / (2.0 * G * l);
}

struct ElasticStepOutcome : StepOutcome {
  bool initiated_now = false;  // the criterion was reached in this step
  bool stiffness_error = false;  // peak beyond delta_f: k too small for this peak; state unchanged
  double peak_f_n = 0.0, peak_f_t = 0.0;  // elastic force at the peak (when initiated_now)
  double peak_delta_e = 0.0;              // delta_0
};

// One straight-line step of an initially elastic bond point from the opening
// (delta_n_old, delta_t_old) to (delta_n, delta_t). History: state, f0, delta_f, delta_m.
inline ElasticStepOutcome step_elastic_bond(double delta_n_old, double delta_t_old,
                                            double delta_n, double delta_t,
                                            const ElasticBondParams& p, ForceDirection dir,
                                            BondState& state, double& f0, double& delta_f,
                                            double& delta_m) {
  ElasticStepOutcome out;
  if (state == BondState::broken) return out;
  const double beta = p.tau_cr / p.sigma_cr;
  if (state == BondState::intact) {
    if (intact_effective_traction(delta_n, delta_t, p, dir) < p.sigma_cr) {
      intact_force(delta_n, delta_t, p.k, beta, dir, out.f_n, out.f_t);
      return out;
    }
    // t_e is continuous along the step but not convex (kink at t_n = 0), so bisection.
    // 64 halvings resolve the crossing to 2^-64 of the step: the peak lies on the
    // criterion to round-off. hi always satisfies t_e >= sigma_cr.
    double lo = 0.0, hi = 1.0;
    if (intact_effective_traction(delta_n_old, delta_t_old, p, dir) >= p.sigma_cr) hi = 0.0;
    for (int it = 0; it < 64 && hi > lo; ++it) {
      const double s = 0.5 * (lo + hi);
      const double te = intact_effective_traction(delta_n_old + s * (delta_n - delta_n_old),
                                                  delta_t_old + s * (delta_t - delta_t_old), p, dir);
      if (te >= p.sigma_cr) hi = s; else lo = s;
    }
    const double pn = delta_n_old + hi * (delta_n - delta_n_old);
    const double pt = delta_t_old + hi * (delta_t - delta_t_old);
    const double d0 = effective_opening(pn, pt, beta);
    const double Fp = p.k * d0;
    const double df = critical_opening(p.G, p.l, Fp);
    out.peak_delta_e = d0;
    intact_force(pn, pt, p.k, beta, dir, out.peak_f_n, out.peak_f_t);
    if (!(d0 < df)) {
      out.stiffness_error = true;
      intact_force(delta_n, delta_t, p.k, beta, dir, out.f_n, out.f_t);
      return out;
    }
    out.initiated_now = true;
    state = BondState::opening;
    delta_f = df;
    f0 = Fp * df / (df - d0);
    delta_m = d0;
  }
  const StepOutcome s = step_opened_bond(delta_n, delta_t, beta, f0, delta_f, delta_m, dir);
  out.f_n = s.f_n;
  out.f_t = s.f_t;
  out.dissipation = s.dissipation;
  out.failed_now = s.failed_now;
  out.mode = s.mode;
  if (s.failed_now) state = BondState::broken;
  return out;
}

}  // namespace cohesive_law
