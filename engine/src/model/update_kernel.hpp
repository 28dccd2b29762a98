// One node's central-difference update and its terms of the energy ledger's
// midpoint-rule works (docs/model.md §3 (7), §4), written once for both
// backends: Model::update_positions (CPU) loops over it, the GPU backend
// launches it per node (cuda/node_update.cu). The sleeping far field stays
// in the CPU's loop around it.
#pragma once
#include <cmath>
#include <cstdint>

#include "common/host_device.hpp"

namespace engine {

struct UpdateArrays {
  double* x;
  double* y;
  double* vx;  // in: v at t - dt/2; out: at t + dt/2
  double* vy;
  const double* mass;
  const double* mass_phys;
  const double* f_x;  // total force, friction included
  const double* f_y;
  const double* f_pre_x;  // before friction
  const double* f_pre_y;
  const double* f_int_x;
  const double* f_int_y;
  const double* f_visc_x;
  const double* f_visc_y;
  const double* f_con_x;
  const double* f_con_y;
  const double* f_coh_x;
  const double* f_coh_y;
  const double* f_buoy_y;
  const double* drag_k;
  const double* r_x;  // boundary reactions
  const double* r_y;
  const double* v_bc_x;  // prescribed velocities at t + dt/2
  const double* v_bc_y;
  const uint8_t* constrained;  // bit 0: x prescribed, bit 1: y
  double dt;
  double g;      // gravity [m/s²], 0 without
  double alpha;  // local (Cundall) damping, 0 without
};

// A node's terms of the step's sums (StepSums without the element energy):
// kinetic sums m v² and the powers of each force with the step's mean velocity.
struct NodeWork {
  double kinetic2_new, kinetic2_old, viscous, local_damping, contact, friction, cohesive, gravity,
      buoyancy, drag, boundary, elastic_new, elastic_old;
};

ICERUBBLE_HD NodeWork update_node(const UpdateArrays& a, int32_t i) {
  const double m = a.mass[i];
  const double vox = a.vx[i], voy = a.vy[i];
  const uint8_t c = a.constrained[i];
  double dfx = 0.0, dfy = 0.0;  // local damping force
  if (a.alpha > 0.0) {
    const double fx = a.f_x[i], fy = a.f_y[i];
    if (!(c & 1) && fx * vox != 0.0) dfx = -a.alpha * fabs(fx) * (vox > 0.0 ? 1.0 : -1.0);
    if (!(c & 2) && fy * voy != 0.0) dfy = -a.alpha * fabs(fy) * (voy > 0.0 ? 1.0 : -1.0);
  }
  const double dt = a.dt;
  const double vnx = (c & 1) ? a.v_bc_x[i] : vox + dt * (a.f_x[i] + dfx) / m;
  const double vny = (c & 2) ? a.v_bc_y[i] : voy + dt * (a.f_y[i] + dfy) / m;
  a.vx[i] = vnx;
  a.vy[i] = vny;
  a.x[i] += dt * vnx;
  a.y[i] += dt * vny;
  // Midpoint-rule power of each force with v(t) = (v^{n-1/2} + v^{n+1/2})/2.
  const double bx = 0.5 * (vox + vnx), by = 0.5 * (voy + vny);
  const double elx = a.f_int_x[i] - a.f_visc_x[i], ely = a.f_int_y[i] - a.f_visc_y[i];
  NodeWork w;
  w.kinetic2_new = m * (vnx * vnx + vny * vny);
  w.kinetic2_old = m * (vox * vox + voy * voy);
  w.viscous = a.f_visc_x[i] * bx + a.f_visc_y[i] * by;
  w.local_damping = dfx * bx + dfy * by;
  w.contact = a.f_con_x[i] * bx + a.f_con_y[i] * by;
  w.friction = (a.f_x[i] - a.f_pre_x[i]) * bx + (a.f_y[i] - a.f_pre_y[i]) * by;
  w.cohesive = a.f_coh_x[i] * bx + a.f_coh_y[i] * by;
  w.gravity = a.mass_phys[i] * a.g * by;  // the weight's power (physical mass), subtracted
  w.buoyancy = a.f_buoy_y[i] * by;
  w.drag = a.drag_k[i] * (vox * bx + voy * by);  // subtracted
  w.boundary = a.r_x[i] * bx + a.r_y[i] * by;
  w.elastic_new = elx * vnx + ely * vny;
  w.elastic_old = elx * vox + ely * voy;
  return w;
}

}  // namespace engine
