#include "cohesive_law/bond_points.hpp"

#include <cmath>
#include <sstream>
#include <stdexcept>

#include "cohesive_law/validation.hpp"

namespace cohesive_law {

namespace {
void check_openings(const double* delta_n, const double* delta_t, std::size_t n) {
  for (std::size_t i = 0; i < n; ++i) {
    if (!std::isfinite(delta_n[i]) || !std::isfinite(delta_t[i])) {
      std::ostringstream s;
      s << "opening of bond point " << i << " is not finite (delta_n = " << delta_n[i]
        << ", delta_t = " << delta_t[i] << ")";
      throw std::invalid_argument(s.str());
    }
  }
}
}  // namespace

std::size_t OpenedBondPoints::add(double f0_, double G, double l, double beta_) {
  require_positive("f0", f0_);
  require_positive("G", G);
  require_positive("l", l);
  require_positive("beta", beta_);
  beta.push_back(beta_);
  f0.push_back(f0_);
  delta_f.push_back(critical_opening(G, l, f0_));
  delta_m.push_back(0.0);
  mode.push_back(static_cast<std::int8_t>(FailureMode::none));
  return f0.size() - 1;
}

void OpenedBondPoints::step(const double* delta_n, const double* delta_t, double* f_n,
                            double* f_t, double* dissipation, std::int8_t* failed_now) {
  const std::size_t n = size();
  check_openings(delta_n, delta_t, n);
  for (std::size_t i = 0; i < n; ++i) {
    const StepOutcome s =
        step_opened_bond(delta_n[i], delta_t[i], beta[i], f0[i], delta_f[i], delta_m[i], direction);
    f_n[i] = s.f_n;
    f_t[i] = s.f_t;
    if (dissipation) dissipation[i] = s.dissipation;
    if (failed_now) failed_now[i] = s.failed_now ? 1 : 0;
    if (s.failed_now) mode[i] = static_cast<std::int8_t>(s.mode);
  }
}

std::size_t ElasticBondPoints::add(const ElasticBondParams& p) {
  validate_strength(p.sigma_cr, p.tau_cr, p.mu);
  require_positive("G", p.G);
  require_positive("l", p.l);
  require_positive("k", p.k);
  const double k_min = min_elastic_stiffness(p.sigma_cr, p.tau_cr, p.G, p.l, direction);
  if (!(p.k > k_min)) {
    std::ostringstream s;
    s << "k must be > " << k_min << " Pa (got " << p.k
      << "): with a softer bond the elastic opening at the peak would reach the critical "
         "opening delta_f = 2 G l / F_p (elastic energy F_p^2/(2k) >= G l)";
    throw std::invalid_argument(s.str());
  }
  params.push_back(p);
  state.push_back(static_cast<std::int8_t>(BondState::intact));
  mode.push_back(static_cast<std::int8_t>(FailureMode::none));
  for (auto* v : {&f0, &delta_f, &delta_m, &delta_0, &peak_f_n, &peak_f_t, &delta_n_prev,
                  &delta_t_prev})
    v->push_back(0.0);
  return params.size() - 1;
}

void ElasticBondPoints::step(const double* delta_n, const double* delta_t, double* f_n,
                             double* f_t, double* dissipation, std::int8_t* initiated_now,
                             std::int8_t* failed_now) {
  const std::size_t n = size();
  check_openings(delta_n, delta_t, n);
  for (std::size_t i = 0; i < n; ++i) {
    BondState st = static_cast<BondState>(state[i]);
    const ElasticStepOutcome s =
        step_elastic_bond(delta_n_prev[i], delta_t_prev[i], delta_n[i], delta_t[i], params[i],
                          direction, st, f0[i], delta_f[i], delta_m[i]);
    if (s.stiffness_error) {
      const ElasticBondParams& p = params[i];
      const double Fp = p.k * s.peak_delta_e;
      std::ostringstream m;
      m << "bond point " << i << ": peak under compression at effective force " << Fp
        << " N/m (t_n = " << s.peak_f_n / p.l << " Pa) stores " << 0.5 * Fp * s.peak_delta_e
        << " J/m elastically, not less than G l = " << p.G * p.l
        << " J/m; raise the stiffness k above " << Fp * Fp / (2.0 * p.G * p.l) << " Pa";
      throw std::runtime_error(m.str());
    }
    state[i] = static_cast<std::int8_t>(st);
    if (s.initiated_now) {
      delta_0[i] = s.peak_delta_e;
      peak_f_n[i] = s.peak_f_n;
      peak_f_t[i] = s.peak_f_t;
    }
    if (s.failed_now) mode[i] = static_cast<std::int8_t>(s.mode);
    delta_n_prev[i] = delta_n[i];
    delta_t_prev[i] = delta_t[i];
    f_n[i] = s.f_n;
    f_t[i] = s.f_t;
    if (dissipation) dissipation[i] = s.dissipation;
    if (initiated_now) initiated_now[i] = s.initiated_now ? 1 : 0;
    if (failed_now) failed_now[i] = s.failed_now ? 1 : 0;
  }
}

double ElasticBondPoints::stored_energy(std::size_t i) const {
  const ElasticBondParams& p = params[i];
  const double beta = p.tau_cr / p.sigma_cr;
  switch (static_cast<BondState>(state[i])) {
    case BondState::intact:
      return intact_stored_energy(delta_n_prev[i], delta_t_prev[i], p.k, beta, direction);
    case BondState::opening:
      return cohesive_law::stored_energy(delta_n_prev[i], delta_t_prev[i], beta, f0[i],
                                         delta_f[i], delta_m[i], direction);
    default:
      return 0.0;
  }
}

}  // namespace cohesive_law
