// One opened bond pair's cohesive force for a step (eqs 8-12; docs/freeze_bonds.md
// "What happens each step", item 3), written once for both backends:
// FreezeBonds::apply (CPU) loops over the opened pairs, the GPU backend takes
// one per lane (cuda/cohesive_forces.cu). It only reads the model and the
// pair's history; the caller scatters the force onto the two nodes and, in a
// committed step, stores the history.
#pragma once
#include <cstdint>

#include "bonds/bond_fields.hpp"
#include "cohesive_law/softening.hpp"
#include "common/host_device.hpp"

namespace engine {

// Rigid phase of an opened pair. Eq 11 has no usable direction while the
// opening is round-off (just split, both nodes at one place), and at a small
// opening delta_e its direction turns with a stiffness |f_c| c/delta_e
// (c = beta for 'paper', beta^2 for 'work_conjugate') that the explicit step
// cannot integrate once it exceeds m_r/dt² (m_r: reduced mass of the two
// nodes): the pair would chatter. So until delta_m has once exceeded
//   delta_r = max(kRigidOpening delta_f, 4 |f0| max(1, c) dt²/m_r)
// the pair acts as a constraint: it holds the nodes together with the
// eq-8 force of the step when that force's effective value is within the
// law's |f_c| = f0 (1 - delta_m/delta_f), and otherwise pulls with |f_c| along
// it (so the crack opens in the direction the elements drive it). Past
// delta_r eq 11 takes over with a direction that is stable to integrate (the
// factor 4 keeps k dt²/m_r <= 1/4, so with an element mode at 0.9 of its
// limit, (w dt)² <= 3.24, the sum stays below 4).
// delta_m, |f_c| and the dissipation follow eq 10 throughout.
constexpr double kRigidOpening = 1e-6;

// What the kernel reads: the nodes (positions, velocities, masses and this
// step's forces) and the pairs' state (bonds/bond_fields.hpp, BondState).
struct CohesivePairArrays {
  const double* x;  // per node
  const double* y;
  const double* vx;
  const double* vy;
  const double* mass;
  const double* f_x;  // every force of the step but friction and the cohesive pairs
  const double* f_y;
  const double* f_con_x;
  const double* f_con_y;
  const int32_t* pair_point;  // per pair
  const int32_t* node_plus;
  const int32_t* node_minus;
  const double* fnx;  // bond normal, fixed at the split
  const double* fny;
  const double* f0;
  const double* delta_f;
  const double* delta_m;
  const double* f_n_prev;  // the law's force and the opening of the last committed step
  const double* f_t_prev;
  const double* d_n_prev;
  const double* d_t_prev;
  const double* beta;  // per bond point: tau_cr / sigma_cr
};

// One pair's step: the force on its + node (the - node takes the opposite),
// the law's state after the step and its energy terms.
struct CohesivePairStep {
  double fpx = 0.0, fpy = 0.0;        // on the + node [N/m]
  double f_n = 0.0, f_t = 0.0;        // the law's force in bond axes (history)
  double delta_n = 0.0, delta_t = 0.0, delta_m = 0.0;
  double work = 0.0, stored = 0.0, dissipation = 0.0;
  bool failed = false;
  int8_t mode = 0;                    // cohesive_law::FailureMode, set when failed
};

// Eq 8 as a vector: with g on the + node and -g on the - node both nodes move
// with the acceleration (F+ + F-)/(m+ + m-) of the unsplit node.
ICERUBBLE_HD void eq8_force(double mp, double mm, double Fpx, double Fpy, double Fmx, double Fmy, double& gx,
                            double& gy) {
  const double m = mp + mm;
  gx = (-mm * Fpx + mp * Fmx) / m;
  gy = (-mm * Fpy + mp * Fmy) / m;
}

// The force that keeps pair k together this step: eq 8 with every force of
// the step but friction and the cohesive pairs (gravity, drag and the contact
// share are proportional to mass and nearly drop out), plus m_r (v- - v+)/dt,
// which also stops a relative velocity the pair already has (stick of a
// rigid-plastic link; 0 at the split, where both nodes share the velocity).
ICERUBBLE_HD void bond_holding_force(const CohesivePairArrays& a, int32_t k, double dt, double& gx, double& gy) {
  const int32_t p = a.node_plus[k], q = a.node_minus[k];
  const double mp = a.mass[p], mm = a.mass[q];
  eq8_force(mp, mm, a.f_x[p] + a.f_con_x[p], a.f_y[p] + a.f_con_y[p], a.f_x[q] + a.f_con_x[q],
            a.f_y[q] + a.f_con_y[q], gx, gy);
  const double s = mp * mm / ((mp + mm) * dt);
  gx += s * (a.vx[q] - a.vx[p]);
  gy += s * (a.vy[q] - a.vy[p]);
}

ICERUBBLE_HD CohesivePairStep cohesive_pair_step(const CohesivePairArrays& a, int32_t k,
                                                 cohesive_law::ForceDirection dir, double dt) {
  namespace cl = cohesive_law;
  CohesivePairStep r;
  const double beta = a.beta[a.pair_point[k]];
  const int32_t ip = a.node_plus[k], im = a.node_minus[k];
  const double nx = a.fnx[k], ny = a.fny[k];
  cl::opening_components(a.x[ip] - a.x[im], a.y[ip] - a.y[im], nx, ny, r.delta_n, r.delta_t);
  double dm = a.delta_m[k];
  // dm < delta_r without a division: dm m+ m- < 4 f0 max(1, c) dt² (m+ + m-)
  const double mp = a.mass[ip], mm = a.mass[im];
  const double c = dir == cl::ForceDirection::paper ? beta : beta * beta;
  const double dt2 = dt * dt;
  const bool rigid = dm < kRigidOpening * a.delta_f[k] ||
                     dm * mp * mm < 4.0 * a.f0[k] * (c > 1.0 ? c : 1.0) * dt2 * (mp + mm);  // std::max's rule
  const cl::StepOutcome s = cl::step_opened_bond(r.delta_n, r.delta_t, beta, a.f0[k], a.delta_f[k], dm, dir);
  r.failed = s.failed_now;
  r.mode = int8_t(s.mode);
  if (rigid) {
    if (!r.failed) {
      double gx, gy;
      bond_holding_force(a, k, dt, gx, gy);
      const double gn = gx * nx + gy * ny, gt = -gx * ny + gy * nx;
      const double F = a.f0[k] * (1.0 - dm / a.delta_f[k]);
      const double geff = cl::initial_effective_force(gn, gt, beta, dir);
      const double scale = geff > F ? F / geff : 1.0;
      r.f_n = -scale * gn;
      r.f_t = -scale * gt;
    }
  } else {
    r.f_n = s.f_n;
    r.f_t = s.f_t;
  }
  double fmx, fmy;
  cl::nodal_forces(r.f_n, r.f_t, nx, ny, r.fpx, r.fpy, fmx, fmy);
  r.work = cl::work_increment(a.f_n_prev[k], a.f_t_prev[k], r.f_n, r.f_t, r.delta_n - a.d_n_prev[k],
                              r.delta_t - a.d_t_prev[k]);
  r.stored = cl::stored_energy(r.delta_n, r.delta_t, beta, a.f0[k], a.delta_f[k], dm, dir);
  r.dissipation = cl::dissipation_increment(a.f0[k], a.delta_f[k], a.delta_m[k], dm);
  r.delta_m = dm;
  return r;
}

// Where a committed step writes the pairs' history and their full failures
// (bonds/bond_fields.hpp's names): BondState's arrays on the CPU, the
// cohesive stage's on the GPU.
struct CohesiveHistory {
  double* delta_m;
  double* f_n_prev;
  double* f_t_prev;
  double* d_n_prev;
  double* d_t_prev;
  PairState* pair_state;
  FailureMode* mode;
  double* t_fail;
  double* x_fail;
  double* y_fail;
  double* dn_fail;
  double* dt_fail;
};

// Pair k's step `r`, taken at `time` from the state in `a`, committed: its
// history, and where it failed fully, its failure record. Returns whether it
// failed.
ICERUBBLE_HD bool commit_pair_step(const CohesiveHistory& h, const CohesivePairArrays& a, int32_t k,
                                   const CohesivePairStep& r, double time) {
  h.delta_m[k] = r.delta_m;
  h.f_n_prev[k] = r.f_n;
  h.f_t_prev[k] = r.f_t;
  h.d_n_prev[k] = r.delta_n;
  h.d_t_prev[k] = r.delta_t;
  if (!r.failed) return false;
  const int32_t ip = a.node_plus[k], im = a.node_minus[k];
  h.pair_state[k] = PairState::failed;
  h.t_fail[k] = time;
  h.x_fail[k] = 0.5 * (a.x[ip] + a.x[im]);
  h.y_fail[k] = 0.5 * (a.y[ip] + a.y[im]);
  h.dn_fail[k] = r.delta_n;
  h.dt_fail[k] = r.delta_t;
  h.mode[k] = FailureMode(r.mode);
  return true;
}

}  // namespace engine
