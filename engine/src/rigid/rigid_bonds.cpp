#include "rigid/rigid_bonds.hpp"

#include <cmath>
#include <string>

#include "common/input_errors.hpp"

namespace engine {

namespace cl = cohesive_law;

void RigidBondPoints::validate_and_reset(int32_t n_bodies) {
  const size_t n = a.size();
  for (auto* v : {&ax, &ay, &bx, &by, &nx, &ny, &k, &l, &sigma_cr, &tau_cr, &mu, &G})
    if (v->size() != n) bad("every bond point array must have " + std::to_string(n) + " entries (one per bond point)");
  if (b.size() != n) bad("a and b must have the same length");
  for (size_t i = 0; i < n; ++i) {
    const std::string at = "bond point " + std::to_string(i) + ": ";
    if (a[i] < 0 || a[i] >= n_bodies || b[i] < 0 || b[i] >= n_bodies || a[i] == b[i])
      bad(at + "bodies (" + std::to_string(a[i]) + ", " + std::to_string(b[i]) +
          ") must be two different ids in [0, " + std::to_string(n_bodies - 1) + "]");
    if (!(std::fabs(std::hypot(nx[i], ny[i]) - 1.0) < 1e-6)) bad(at + "the normal must be a unit vector");
    for (double v : {ax[i], ay[i], bx[i], by[i]})
      if (!std::isfinite(v)) bad(at + "anchors must be finite");
    if (!(k[i] > 0.0) || !std::isfinite(k[i])) bad(at + "k must be > 0 Pa and finite (got " + num(k[i]) + ")");
    if (!(l[i] > 0.0) || !std::isfinite(l[i])) bad(at + "l must be > 0 m and finite (got " + num(l[i]) + ")");
    if (!(sigma_cr[i] > 0.0) || !std::isfinite(sigma_cr[i])) bad(at + "sigma_cr must be > 0 Pa (got " + num(sigma_cr[i]) + ")");
    if (!(tau_cr[i] > 0.0) || !std::isfinite(tau_cr[i])) bad(at + "tau_cr must be > 0 Pa (got " + num(tau_cr[i]) + ")");
    if (!(mu[i] >= 0.0) || !std::isfinite(mu[i])) bad(at + "mu must be >= 0 (got " + num(mu[i]) + ")");
    if (!(G[i] > 0.0) || !std::isfinite(G[i])) bad(at + "G must be > 0 J/m² (got " + num(G[i]) + ")");
    const double k_min = cl::min_elastic_stiffness(sigma_cr[i], tau_cr[i], G[i], l[i], direction);
    if (!(k[i] > k_min))
      bad(at + "k = " + num(k[i]) + " Pa must exceed F_p²/(2 G l) = " + num(k_min) +
          " Pa (else the peak lies beyond the failure opening delta_f)");
  }
  state.assign(n, int8_t(cl::BondState::intact));
  for (auto* v : {&f0, &delta_f, &delta_m, &dn_prev, &dt_prev, &dissipated, &f_n, &f_t}) v->assign(n, 0.0);
  t_initiated.assign(n, NAN);
  t_failed.assign(n, NAN);
  mode.assign(n, int8_t(cl::FailureMode::none));
}

void RigidBondPoints::step(int32_t n_bodies, const double* x, const double* y, const double* theta,
                           double time, double* fx, double* fy, double* tz) {
  for (int32_t j = 0; j < n_bodies; ++j) fx[j] = fy[j] = tz[j] = 0.0;
  const bool released = failure && !failure_last_step;
  failure_last_step = failure;
  for (int32_t i = 0; i < size(); ++i) {
    f_n[i] = f_t[i] = 0.0;
    if (state[i] == int8_t(cl::BondState::broken)) continue;
    const int32_t A = a[i], B = b[i];
    const double ca = std::cos(theta[A]), sa = std::sin(theta[A]);
    const double cb = std::cos(theta[B]), sb = std::sin(theta[B]);
    const double rax = ca * ax[i] - sa * ay[i], ray = sa * ax[i] + ca * ay[i];  // from a's centroid
    const double rbx = cb * bx[i] - sb * by[i], rby = sb * bx[i] + cb * by[i];
    const double ux = (x[B] + rbx) - (x[A] + rax), uy = (y[B] + rby) - (y[A] + ray);
    const double n_x = ca * nx[i] - sa * ny[i], n_y = sa * nx[i] + ca * ny[i];
    const double t_x = -n_y, t_y = n_x;
    const double dn = ux * n_x + uy * n_y, dt = ux * t_x + uy * t_y;
    cl::ElasticBondParams p{k[i], l[i], sigma_cr[i], tau_cr[i], mu[i], G[i]};
    cl::BondState s = cl::BondState(state[i]);
    cl::ElasticStepOutcome o;
    if (!failure && s == cl::BondState::intact)
      cl::intact_force(dn, dt, p.k, p.tau_cr / p.sigma_cr, direction, o.f_n, o.f_t);
    else
      o = cl::step_elastic_bond(dn_prev[i], dt_prev[i], dn, dt, p, direction, s, f0[i], delta_f[i], delta_m[i]);
    if (o.stiffness_error && released) {
      // held past its peak while settling, with more elastic energy than the
      // crack can take: it breaks at once (its G l booked as dissipated)
      o = cl::ElasticStepOutcome{};
      s = cl::BondState::broken;
      o.initiated_now = o.failed_now = true;
      o.mode = cl::failure_mode(dn, dt);
      o.dissipation = G[i] * l[i];
    } else if (o.stiffness_error) {
      bad("bond point " + std::to_string(i) + " at t = " + num(time) + " s: its peak under compression lies " +
          "beyond delta_f; raise the bond stiffness k (now " + num(k[i]) + " Pa)");
    }
    if (o.initiated_now) t_initiated[i] = time;
    if (o.failed_now) {
      t_failed[i] = time;
      mode[i] = int8_t(o.mode);
    }
    state[i] = int8_t(s);
    dissipated[i] += o.dissipation;
    dn_prev[i] = dn;
    dt_prev[i] = dt;
    f_n[i] = o.f_n;
    f_t[i] = o.f_t;
    const double Fx = -(o.f_n * n_x + o.f_t * t_x), Fy = -(o.f_n * n_y + o.f_t * t_y);  // on b
    // both act at the anchors' midpoint: equal, opposite and on one line, so
    // the pair's angular momentum is kept (at its own anchors they would make
    // a couple u x f)
    const double mx = 0.5 * ((x[A] + rax) + (x[B] + rbx)), my = 0.5 * ((y[A] + ray) + (y[B] + rby));
    fx[B] += Fx;
    fy[B] += Fy;
    tz[B] += (mx - x[B]) * Fy - (my - y[B]) * Fx;
    fx[A] -= Fx;
    fy[A] -= Fy;
    tz[A] -= (mx - x[A]) * Fy - (my - y[A]) * Fx;
  }
}

double RigidBondPoints::stored_energy() const {
  double e = 0.0;
  for (int32_t i = 0; i < size(); ++i) {
    const double beta = tau_cr[i] / sigma_cr[i];
    if (state[i] == int8_t(cl::BondState::intact)) {
      e += cl::intact_stored_energy(dn_prev[i], dt_prev[i], k[i], beta, direction);
    } else if (state[i] == int8_t(cl::BondState::opening)) {
      // on the secant to the origin: 1/2 F(delta_m) delta_e^2 / delta_m
      const double de = cl::effective_opening(dn_prev[i], dt_prev[i], beta);
      const double F = cl::softening_force(delta_m[i], delta_m[i], delta_f[i], f0[i]);
      if (delta_m[i] > 0.0) e += 0.5 * F * de * de / delta_m[i];
    }
  }
  return e;
}

}  // namespace engine
