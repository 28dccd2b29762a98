#include "element/cst_element.hpp"

namespace engine {

double element_reference(double X0, double Y0, double X1, double Y1, double X2, double Y2,
                         double& b00, double& b01, double& b10, double& b11) {
  const double d00 = X1 - X0, d01 = X2 - X0;  // Dm = [[d00, d01], [d10, d11]]
  const double d10 = Y1 - Y0, d11 = Y2 - Y0;
  const double det = d00 * d11 - d01 * d10;
  if (!(det > 0.0)) {
    b00 = b01 = b10 = b11 = 0.0;
    return 0.5 * det;
  }
  const double inv = 1.0 / det;
  b00 = d11 * inv;
  b01 = -d01 * inv;
  b10 = -d10 * inv;
  b11 = d00 * inv;
  return 0.5 * det;
}

namespace {

// Deformation gradient of triangle t from corner coordinates.
struct Kinematics {
  double F11, F12, F21, F22;
};

inline Kinematics gradient(double ax, double ay, double bx, double by, double cx, double cy,
                           double b00, double b01, double b10, double b11) {
  const double e1x = bx - ax, e1y = by - ay, e2x = cx - ax, e2y = cy - ay;
  return {e1x * b00 + e2x * b10, e1x * b01 + e2x * b11, e1y * b00 + e2y * b10,
          e1y * b01 + e2y * b11};
}

// Corner forces f = -A0 P Dm^-T of a first Piola-Kirchhoff stress P into an
// (x, y) field pair of the triangle's three corner records, f pointing at the
// pair in the first; corner 0 balances the other two, so the sum is exactly zero.
inline void corner_forces(double P11, double P12, double P21, double P22, double a0, double b00,
                          double b01, double b10, double b11, double* f) {
  constexpr int s = CornerLoad::stride;
  const double f1x = -a0 * (P11 * b00 + P12 * b01), f1y = -a0 * (P21 * b00 + P22 * b01);
  const double f2x = -a0 * (P11 * b10 + P12 * b11), f2y = -a0 * (P21 * b10 + P22 * b11);
  f[0] = -(f1x + f2x);
  f[1] = -(f1y + f2y);
  f[s] = f1x;
  f[s + 1] = f1y;
  f[2 * s] = f2x;
  f[2 * s + 1] = f2y;
}

}  // namespace

void element_forces(const Nodes& nodes, Triangles& tris, const std::vector<ElementMaterial>& mat,
                    bool damping, int32_t begin, int32_t end, ElementSweep& out,
                    const int32_t* list) {
  const double* __restrict x = nodes.x.data();
  const double* __restrict y = nodes.y.data();
  const double* __restrict vx = nodes.vx.data();
  const double* __restrict vy = nodes.vy.data();
  const int32_t* __restrict tn = tris.node.data();
  const int32_t* __restrict body = tris.body.data();
  const double* __restrict B00 = tris.binv00.data();
  const double* __restrict B01 = tris.binv01.data();
  const double* __restrict B10 = tris.binv10.data();
  const double* __restrict B11 = tris.binv11.data();
  const double* __restrict A0 = tris.area0.data();
  double* __restrict sig = tris.stress.data();
  double* __restrict load = tris.corner_load.data();
  constexpr int rec = 3 * CornerLoad::stride;  // a triangle's three corner records
  double* __restrict W = tris.energy.data();
  const ElementMaterial* __restrict em = mat.data();

  // continue the sweep's sums (a thread's block may come in chunks)
  double energy = out.elastic_energy;
  int32_t inverted = out.inverted;
  for (int32_t j = begin; j < end; ++j) {
    const int32_t t = list ? list[j] : j;
    const int32_t i0 = tn[3 * t], i1 = tn[3 * t + 1], i2 = tn[3 * t + 2];
    const double b00 = B00[t], b01 = B01[t], b10 = B10[t], b11 = B11[t];
    const double a0 = A0[t];
    const ElementMaterial& m = em[body[t]];
    const Kinematics k = gradient(x[i0], y[i0], x[i1], y[i1], x[i2], y[i2], b00, b01, b10, b11);

    // Green-Lagrange strain and St Venant-Kirchhoff stress (plane strain).
    const double E11 = 0.5 * (k.F11 * k.F11 + k.F21 * k.F21 - 1.0);
    const double E22 = 0.5 * (k.F12 * k.F12 + k.F22 * k.F22 - 1.0);
    const double E12 = 0.5 * (k.F11 * k.F12 + k.F21 * k.F22);
    const double trE = E11 + E22;
    const double S11 = m.lambda * trE + 2.0 * m.shear_modulus * E11;
    const double S22 = m.lambda * trE + 2.0 * m.shear_modulus * E22;
    const double S12 = 2.0 * m.shear_modulus * E12;
    const double w = a0 * (0.5 * m.lambda * trE * trE + m.shear_modulus * (E11 * E11 + E22 * E22 + 2.0 * E12 * E12));
    W[t] = w;
    energy += w;

    // First Piola-Kirchhoff stress of the elastic part, P = F S.
    const double P11 = k.F11 * S11 + k.F12 * S12, P12 = k.F11 * S12 + k.F12 * S22;
    const double P21 = k.F21 * S11 + k.F22 * S12, P22 = k.F21 * S12 + k.F22 * S22;
    const double J = k.F11 * k.F22 - k.F12 * k.F21;
    if (!(J > 0.0) && inverted < 0) inverted = t;
    const double iJ = 1.0 / J;
    sig[3 * t] = (P11 * k.F11 + P12 * k.F12) * iJ;
    sig[3 * t + 1] = (P21 * k.F21 + P22 * k.F22) * iJ;
    sig[3 * t + 2] = (P11 * k.F21 + P12 * k.F22) * iJ;

    double Q11 = P11, Q12 = P12, Q21 = P21, Q22 = P22;  // total P
    if (damping) {
      // Rate of Green strain dE/dt = sym(F^T dF/dt) with the velocities at
      // t - dt/2: objective, so a spinning body feels no damping.
      const Kinematics r = gradient(vx[i0], vy[i0], vx[i1], vy[i1], vx[i2], vy[i2], b00, b01, b10, b11);
      const double D11 = k.F11 * r.F11 + k.F21 * r.F21;
      const double D22 = k.F12 * r.F12 + k.F22 * r.F22;
      const double D12 = 0.5 * (k.F11 * r.F12 + k.F21 * r.F22 + k.F12 * r.F11 + k.F22 * r.F21);
      const double trD = D11 + D22;
      const double V11 = m.tau * (m.lambda * trD + 2.0 * m.shear_modulus * D11) + m.eta * D11;
      const double V22 = m.tau * (m.lambda * trD + 2.0 * m.shear_modulus * D22) + m.eta * D22;
      const double V12 = m.tau * 2.0 * m.shear_modulus * D12 + m.eta * D12;
      const double W11 = k.F11 * V11 + k.F12 * V12, W12 = k.F11 * V12 + k.F12 * V22;
      const double W21 = k.F21 * V11 + k.F22 * V12, W22 = k.F21 * V12 + k.F22 * V22;
      corner_forces(W11, W12, W21, W22, a0, b00, b01, b10, b11, load + rec * t + CornerLoad::visc_x);
      Q11 += W11;
      Q12 += W12;
      Q21 += W21;
      Q22 += W22;
    }
    corner_forces(Q11, Q12, Q21, Q22, a0, b00, b01, b10, b11, load + rec * t + CornerLoad::fx);
  }
  out.elastic_energy = energy;
  out.inverted = inverted;
}

double element_strain_energy(const Nodes& nodes, const Triangles& tris,
                             const std::vector<ElementMaterial>& mat, int32_t t) {
  const int32_t i0 = tris.node[3 * t], i1 = tris.node[3 * t + 1], i2 = tris.node[3 * t + 2];
  const Kinematics k = gradient(nodes.x[i0], nodes.y[i0], nodes.x[i1], nodes.y[i1], nodes.x[i2],
                                nodes.y[i2], tris.binv00[t], tris.binv01[t], tris.binv10[t],
                                tris.binv11[t]);
  const ElementMaterial& m = mat[tris.body[t]];
  const double E11 = 0.5 * (k.F11 * k.F11 + k.F21 * k.F21 - 1.0);
  const double E22 = 0.5 * (k.F12 * k.F12 + k.F22 * k.F22 - 1.0);
  const double E12 = 0.5 * (k.F11 * k.F12 + k.F21 * k.F22);
  const double trE = E11 + E22;
  return tris.area0[t] *
         (0.5 * m.lambda * trE * trE + m.shear_modulus * (E11 * E11 + E22 * E22 + 2.0 * E12 * E12));
}

}  // namespace engine
