// One bond point's check (eqs 5-7; docs/freeze_bonds.md "What happens each
// step", items 1-2), written once for both backends: FreezeBonds::check (CPU)
// loops over the intact points, the GPU backend takes one per lane
// (cuda/bond_check.cu). It only reads the model; the split plan is the
// points whose ratio reaches 1.
#pragma once
#include <cmath>
#include <cstdint>

#include "cohesive_law/criterion.hpp"
#include "common/host_device.hpp"

namespace engine {

struct BondCheckArrays {
  const double* x;  // node positions
  const double* y;
  const int32_t* gather_start;  // NodeGather: a node's triangle corners
  const int32_t* gather_slot;
  const double* stress;  // per triangle: elastic Cauchy stress (sxx, syy, sxy)
  const double* area0;   // per triangle
  const int32_t* point_node;  // per bond point
  const int32_t* first_pair;
  const int32_t* n_pairs;
  const double* sigma_cr;
  const double* tau_cr;
  const double* beta;  // tau_cr / sigma_cr
  const int32_t* frame_p;  // per pair: its frame edge, reference edge and normal
  const int32_t* frame_q;
  const double* d0x;
  const double* d0y;
  const double* n0x;
  const double* n0y;
  double* tn;  // per pair, out: the traction of this check
  double* tt;
};

// Area-weighted elastic Cauchy stress around a node (eq 7).
ICERUBBLE_HD void bond_mean_stress(const BondCheckArrays& a, int32_t node, double& sxx, double& syy,
                                   double& sxy) {
  double w_sum = 0.0, xx = 0.0, yy = 0.0, xy = 0.0;
  for (int32_t j = a.gather_start[node]; j < a.gather_start[node + 1]; ++j) {
    const int32_t t = a.gather_slot[j] / 3;
    const double w = a.area0[t];
    w_sum += w;
    xx += w * a.stress[3 * t];
    yy += w * a.stress[3 * t + 1];
    xy += w * a.stress[3 * t + 2];
  }
  sxx = xx / w_sum;
  syy = yy / w_sum;
  sxy = xy / w_sum;
}

// Current normal of an intact pair: the reference normal turned by the
// rotation of its frame edge.
ICERUBBLE_HD void bond_current_normal(const BondCheckArrays& a, int32_t k, double& nx, double& ny) {
  const double dx = a.x[a.frame_q[k]] - a.x[a.frame_p[k]];
  const double dy = a.y[a.frame_q[k]] - a.y[a.frame_p[k]];
  // rotation from the reference frame edge d0 to its current direction d
  double c = a.d0x[k] * dx + a.d0y[k] * dy;
  double s = a.d0x[k] * dy - a.d0y[k] * dx;
  const double r = 1.0 / sqrt(c * c + s * s);  // |d0| |d|, never 0 for a valid mesh
  c *= r;
  s *= r;
  nx = c * a.n0x[k] - s * a.n0y[k];
  ny = s * a.n0x[k] + c * a.n0y[k];
}

// Largest t_e / sigma_cr over the pairs of point p (>= 1 exactly when eq 5
// is reached by one of them; below 1 otherwise), and each pair's traction.
ICERUBBLE_HD double bond_point_ratio(const BondCheckArrays& a, int32_t p, double mu) {
  double sxx, syy, sxy;
  bond_mean_stress(a, a.point_node[p], sxx, syy, sxy);
  double worst = -INFINITY;
  bool reached = false;
  for (int32_t k = a.first_pair[p]; k < a.first_pair[p] + a.n_pairs[p]; ++k) {
    double nx, ny;
    bond_current_normal(a, k, nx, ny);
    // eq 7: t = sigma n; normal and tangential (t = (-n_y, n_x)) parts
    const double tx = sxx * nx + sxy * ny, ty = sxy * nx + syy * ny;
    const double t_n = tx * nx + ty * ny, t_t = -tx * ny + ty * nx;
    a.tn[k] = t_n;
    a.tt[k] = t_t;
    reached = reached || cohesive_law::criterion_reached(t_n, t_t, a.sigma_cr[p], a.tau_cr[p], mu);
    const double r = cohesive_law::effective_traction(t_n, t_t, a.beta[p], mu) / a.sigma_cr[p];
    worst = worst < r ? r : worst;  // std::max's rule, NaN included
  }
  // The split decision is eq 5 itself; the ratio only steers the screening.
  const double below_one = nextafter(1.0, 0.0);
  return reached ? (worst < 1.0 ? 1.0 : worst) : (below_one < worst ? below_one : worst);  // std::max, std::min
}

}  // namespace engine
