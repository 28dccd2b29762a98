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

CstArrays cst_arrays(const Nodes& nodes, Triangles& tris, const std::vector<ElementMaterial>& mat) {
  return {nodes.x.data(),       nodes.y.data(),       nodes.vx.data(),      nodes.vy.data(),
          tris.node.data(),     tris.body.data(),     tris.binv00.data(),   tris.binv01.data(),
          tris.binv10.data(),   tris.binv11.data(),   tris.area0.data(),    mat.data(),
          tris.stress.data(),   tris.energy.data()};
}

void element_forces(const Nodes& nodes, Triangles& tris, const std::vector<ElementMaterial>& mat,
                    bool damping, int32_t begin, int32_t end, ElementSweep& out,
                    const int32_t* list) {
  const CstArrays a = cst_arrays(nodes, tris, mat);
  const CornerRecords load{tris.corner_load.data()};
  // continue the sweep's sums (a thread's block may come in chunks)
  double energy = out.elastic_energy;
  int32_t inverted = out.inverted;
  for (int32_t j = begin; j < end; ++j) {
    const int32_t t = list ? list[j] : j;
    bool flipped = false;
    energy += cst_triangle(a, load, damping, t, flipped);
    if (flipped && inverted < 0) inverted = t;
  }
  out.elastic_energy = energy;
  out.inverted = inverted;
}

double element_strain_energy(const Nodes& nodes, const Triangles& tris,
                             const std::vector<ElementMaterial>& mat, int32_t t) {
  const int32_t i0 = tris.node[3 * t], i1 = tris.node[3 * t + 1], i2 = tris.node[3 * t + 2];
  const Kinematics k = cst_gradient(nodes.x[i0], nodes.y[i0], nodes.x[i1], nodes.y[i1], nodes.x[i2],
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
