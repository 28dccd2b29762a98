// Freeze-bond failure criterion (Polojärvi & Tuhkuri 2013, eqs 5-6).
// Pure scalar functions, cheap enough to inline in the engine's bond-point loop.
#pragma once

#include <cmath>

#include "cohesive_law/host_device.hpp"

namespace cohesive_law {

// Effective traction t_e of eq 6 for the normal (t_n, tension positive) and
// tangential (t_t) traction at a bond point; beta = tau_cr / sigma_cr.
// On the compressive side friction of the closed crack (contact, docs/model.md §3.2)
// carries mu |t_n| of the shear, so only the excess counts (the paper's reason:
// otherwise a crack opened at |t_t| = tau_cr would be arrested by friction).
// t_e can be negative under strong compression; that simply means "far from failure".
COHESIVE_LAW_HD double effective_traction(double t_n, double t_t, double beta, double mu) {
  if (t_n >= 0.0) return sqrt(t_t * t_t / (beta * beta) + t_n * t_n);
  return (fabs(t_t) - mu * fabs(t_n)) / beta;
}

// Eq 5: the bond point starts to open when t_e >= sigma_cr. In pure tension this is
// t_n = sigma_cr, in pure shear |t_t| = tau_cr, under compression
// |t_t| = tau_cr + mu |t_n|, and for t_n >= 0 the ellipse (t_n/sigma_cr)^2 + (t_t/tau_cr)^2 = 1.
COHESIVE_LAW_HD bool criterion_reached(double t_n, double t_t, double sigma_cr, double tau_cr, double mu) {
  return effective_traction(t_n, t_t, tau_cr / sigma_cr, mu) >= sigma_cr;
}

}  // namespace cohesive_law
