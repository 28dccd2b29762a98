// One touching pair's Coulomb friction (eq 4 with an exact stick state;
// contact/friction.cpp), written once for both backends: ContactSolver::
// apply_friction (CPU) runs the pairs colour by colour (contact/
// friction_order.hpp), the GPU backend a lane per pair of a colour
// (cuda/friction.cu). A pair is given by its six nodes (contactor's, then
// target's), the shape functions of the contact point on each triangle and
// the unit normal; the tangent is (-ny, nx). The node arrays w (velocities at
// the end of the step) and im (inverse masses per component) are the solver's
// workspace.
#pragma once
#include <cmath>
#include <cstdint>

#include "common/host_device.hpp"

namespace engine {

// A node's inverse mass per component (0 for an immovable or prescribed
// component) and its velocity at the end of the step without friction,
// v' = v + dt f/m (the prescribed velocity where a component is prescribed).
ICERUBBLE_HD void friction_predict_node(double mass, uint8_t constrained, double vx, double vy, double fx,
                                        double fy, const double* v_bc_x, const double* v_bc_y, int32_t n,
                                        double dt, double& imx, double& imy, double& wx, double& wy) {
  const double im = (mass > 0.0 && mass < INFINITY) ? 1.0 / mass : 0.0;
  imx = (constrained & 1) ? 0.0 : im;
  imy = (constrained & 2) ? 0.0 : im;
  if (constrained & 1)
    wx = v_bc_x ? v_bc_x[n] : vx;
  else
    wx = vx + dt * fx * im;
  if (constrained & 2)
    wy = v_bc_y ? v_bc_y[n] : vy;
  else
    wy = vy + dt * fy * im;
}

// The change of the pair's tangential relative velocity per unit tangential
// force and unit dt (its inverse effective mass along the tangent).
ICERUBBLE_HD double friction_inverse_mass(const int32_t* node, const double* nc, const double* nt, double nx,
                                          double ny, const double* imx, const double* imy) {
  const double tx2 = ny * ny, ty2 = nx * nx;
  double k = 0.0;
  for (int j = 0; j < 3; ++j) {
    const int32_t a = node[j], b = node[3 + j];
    k += nc[j] * nc[j] * (tx2 * imx[a] + ty2 * imy[a]);
    k += nt[j] * nt[j] * (tx2 * imx[b] + ty2 * imy[b]);
  }
  return k;
}

// Tangential relative velocity of the contactor against the target at the
// contact point, with the end-of-step velocities w.
ICERUBBLE_HD double friction_slip(const int32_t* node, const double* nc, const double* nt, double nx, double ny,
                                  const double* wx, const double* wy) {
  double ux = 0.0, uy = 0.0;
  for (int j = 0; j < 3; ++j) {
    ux += nc[j] * wx[node[j]] - nt[j] * wx[node[3 + j]];
    uy += nc[j] * wy[node[j]] - nt[j] * wy[node[3 + j]];
  }
  return -ny * ux + nx * uy;  // along the tangent (-ny, nx)
}

// Adds the change d of the pair's tangential force to the end-of-step
// velocities of its nodes.
ICERUBBLE_HD void friction_push(const int32_t* node, const double* nc, const double* nt, double nx, double ny,
                                double d, double dt, const double* imx, const double* imy, double* wx,
                                double* wy) {
  const double tx = -ny, ty = nx;
  for (int j = 0; j < 3; ++j) {
    const int32_t a = node[j], b = node[3 + j];
    const double ia = dt * d * nc[j], ib = dt * d * nt[j];
    wx[a] += ia * imx[a] * tx;
    wy[a] += ia * imy[a] * ty;
    wx[b] -= ib * imx[b] * tx;
    wy[b] -= ib * imy[b] * ty;
  }
}

// std::clamp's result (NaN stays NaN), which device code cannot call.
ICERUBBLE_HD double clamp_to_cone(double v, double limit) {
  return v < -limit ? -limit : (limit < v ? limit : v);
}

// One projected Gauss-Seidel update of the pair's tangential force lambda
// (|lambda| <= limit = mu |f_c|): the force that stops the slip if it is
// within the cone, else the cone's edge. Returns the change (0: none), which
// the caller pushes onto the velocities.
ICERUBBLE_HD double friction_update(const int32_t* node, const double* nc, const double* nt, double nx, double ny,
                                    double limit, double kinv, double dt, const double* wx, const double* wy,
                                    double& lambda) {
  const double wt = friction_slip(node, nc, nt, nx, ny, wx, wy);
  const double lam = clamp_to_cone(lambda - wt / (dt * kinv), limit);
  const double d = lam - lambda;
  lambda = lam;
  return d;
}

// Index of key in keys[0, n) (ascending), or -1: the warm-start lookup.
ICERUBBLE_HD int64_t find_key(const uint64_t* keys, int64_t n, uint64_t key) {
  int64_t lo = 0, hi = n;
  while (lo < hi) {
    const int64_t mid = lo + (hi - lo) / 2;
    if (keys[mid] < key)
      lo = mid + 1;
    else
      hi = mid;
  }
  return (lo < n && keys[lo] == key) ? lo : -1;
}

// A pair's identity across steps: (contactor, target) triangle ids.
ICERUBBLE_HD uint64_t friction_pair_key(int32_t contactor, int32_t target) {
  return (uint64_t(uint32_t(contactor)) << 32) | uint32_t(target);
}

// The priority of a pair in the sweeps' colouring (contact/friction_order.hpp):
// a fixed mix of its key (splitmix64's finaliser), so that neighbouring pairs
// come in no particular order and the colouring's chains stay short.
ICERUBBLE_HD uint64_t friction_priority(uint64_t key) {
  key ^= key >> 30;
  key *= 0xbf58476d1ce4e5b9ull;
  key ^= key >> 27;
  key *= 0x94d049bb133111ebull;
  key ^= key >> 31;
  return key;
}

// Whether pair q (priority pq) is coloured before pair p (priority pp): by
// priority, ties by pair index.
ICERUBBLE_HD bool coloured_before(uint64_t pq, int32_t q, uint64_t pp, int32_t p) {
  return pq != pp ? pq < pp : q < p;
}

}  // namespace engine
