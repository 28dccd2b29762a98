// One constant-strain triangle's physics (docs/model.md §3.1), written once
// for both backends: element_forces (CPU) loops over it, the GPU backend
// launches it per triangle (cuda/body_forces.cu). The arithmetic and its
// order are the CPU engine's, so both give the same bits.
#pragma once
#include <cstdint>

#include "common/corner_layout.hpp"
#include "common/host_device.hpp"
#include "common/mesh_arrays.hpp"
#include "element/material.hpp"

namespace engine {

// What the element pass reads and writes, as flat arrays (host or device).
struct CstArrays {
  const double* x;
  const double* y;
  const double* vx;  // velocities at t - dt/2: the damping stress only
  const double* vy;
  const int32_t* node;  // 3 per triangle
  const int32_t* body;
  const double* binv00;
  const double* binv01;
  const double* binv10;
  const double* binv11;
  const double* area0;
  const ElementMaterial* material;  // per body
  double* stress;       // 3 per triangle
  double* energy;       // per triangle
};

// Deformation gradient of a triangle from corner coordinates.
struct Kinematics {
  double F11, F12, F21, F22;
};

ICERUBBLE_HD Kinematics cst_gradient(double ax, double ay, double bx, double by, double cx,
                                     double cy, double b00, double b01, double b10, double b11) {
  const double e1x = bx - ax, e1y = by - ay, e2x = cx - ax, e2y = cy - ay;
  return {e1x * b00 + e2x * b10, e1x * b01 + e2x * b11, e1y * b00 + e2y * b10,
          e1y * b01 + e2y * b11};
}

// Corner forces f = -A0 P Dm^-T of a first Piola-Kirchhoff stress P into the
// (x, y) field pair starting at field `fx` of the triangle's three corners
// (slots slot0, slot0 + 1, slot0 + 2); corner 0 balances the other two, so
// the sum is exactly zero.
template <class Corners>
ICERUBBLE_HD void cst_corner_forces(double P11, double P12, double P21, double P22, double a0,
                                    double b00, double b01, double b10, double b11, Corners load,
                                    size_t slot0, int fx) {
  const double f1x = -a0 * (P11 * b00 + P12 * b01), f1y = -a0 * (P21 * b00 + P22 * b01);
  const double f2x = -a0 * (P11 * b10 + P12 * b11), f2y = -a0 * (P21 * b10 + P22 * b11);
  load(slot0, fx) = -(f1x + f2x);
  load(slot0, fx + 1) = -(f1y + f2y);
  load(slot0 + 1, fx) = f1x;
  load(slot0 + 1, fx + 1) = f1y;
  load(slot0 + 2, fx) = f2x;
  load(slot0 + 2, fx + 1) = f2y;
}

// Triangle t: Green-Lagrange strain, St Venant-Kirchhoff stress (plane
// strain), the damping stress when asked, corner forces, Cauchy stress and
// strain energy. Returns the strain energy A0 W(E) [J/m]; `inverted` is set
// when det F <= 0. Corner forces go to `load` (common/corner_layout.hpp).
template <class Corners>
ICERUBBLE_HD double cst_triangle(const CstArrays& a, Corners load, bool damping, int32_t t, bool& inverted) {
  const int32_t i0 = a.node[3 * t], i1 = a.node[3 * t + 1], i2 = a.node[3 * t + 2];
  const double b00 = a.binv00[t], b01 = a.binv01[t], b10 = a.binv10[t], b11 = a.binv11[t];
  const double a0 = a.area0[t];
  const ElementMaterial& m = a.material[a.body[t]];
  const Kinematics k = cst_gradient(a.x[i0], a.y[i0], a.x[i1], a.y[i1], a.x[i2], a.y[i2], b00, b01, b10, b11);

  // Green-Lagrange strain and St Venant-Kirchhoff stress (plane strain).
  const double E11 = 0.5 * (k.F11 * k.F11 + k.F21 * k.F21 - 1.0);
  const double E22 = 0.5 * (k.F12 * k.F12 + k.F22 * k.F22 - 1.0);
  const double E12 = 0.5 * (k.F11 * k.F12 + k.F21 * k.F22);
  const double trE = E11 + E22;
  const double S11 = m.lambda * trE + 2.0 * m.shear_modulus * E11;
  const double S22 = m.lambda * trE + 2.0 * m.shear_modulus * E22;
  const double S12 = 2.0 * m.shear_modulus * E12;
  const double w = a0 * (0.5 * m.lambda * trE * trE + m.shear_modulus * (E11 * E11 + E22 * E22 + 2.0 * E12 * E12));
  a.energy[t] = w;

  // First Piola-Kirchhoff stress of the elastic part, P = F S.
  const double P11 = k.F11 * S11 + k.F12 * S12, P12 = k.F11 * S12 + k.F12 * S22;
  const double P21 = k.F21 * S11 + k.F22 * S12, P22 = k.F21 * S12 + k.F22 * S22;
  const double J = k.F11 * k.F22 - k.F12 * k.F21;
  inverted = !(J > 0.0);
  const double iJ = 1.0 / J;
  a.stress[3 * t] = (P11 * k.F11 + P12 * k.F12) * iJ;
  a.stress[3 * t + 1] = (P21 * k.F21 + P22 * k.F22) * iJ;
  a.stress[3 * t + 2] = (P11 * k.F21 + P12 * k.F22) * iJ;

  const size_t slot0 = 3 * size_t(t);
  double Q11 = P11, Q12 = P12, Q21 = P21, Q22 = P22;  // total P
  if (damping) {
    // Rate of Green strain dE/dt = sym(F^T dF/dt) with the velocities at
    // t - dt/2: objective, so a spinning body feels no damping.
    const Kinematics r = cst_gradient(a.vx[i0], a.vy[i0], a.vx[i1], a.vy[i1], a.vx[i2], a.vy[i2], b00, b01, b10, b11);
    const double D11 = k.F11 * r.F11 + k.F21 * r.F21;
    const double D22 = k.F12 * r.F12 + k.F22 * r.F22;
    const double D12 = 0.5 * (k.F11 * r.F12 + k.F21 * r.F22 + k.F12 * r.F11 + k.F22 * r.F21);
    const double trD = D11 + D22;
    const double V11 = m.tau * (m.lambda * trD + 2.0 * m.shear_modulus * D11) + m.eta * D11;
    const double V22 = m.tau * (m.lambda * trD + 2.0 * m.shear_modulus * D22) + m.eta * D22;
    const double V12 = m.tau * 2.0 * m.shear_modulus * D12 + m.eta * D12;
    const double W11 = k.F11 * V11 + k.F12 * V12, W12 = k.F11 * V12 + k.F12 * V22;
    const double W21 = k.F21 * V11 + k.F22 * V12, W22 = k.F21 * V12 + k.F22 * V22;
    cst_corner_forces(W11, W12, W21, W22, a0, b00, b01, b10, b11, load, slot0, CornerLoad::visc_x);
    Q11 += W11;
    Q12 += W12;
    Q21 += W21;
    Q22 += W22;
  }
  cst_corner_forces(Q11, Q12, Q21, Q22, a0, b00, b01, b10, b11, load, slot0, CornerLoad::fx);
  return w;
}

}  // namespace engine
