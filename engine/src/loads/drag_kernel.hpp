// One body's quadratic drag constant c_b = 1/2 rho_w C_d |V| L (docs/model.md
// §3.4), written once for both backends: body_drag_constants (CPU) loops over
// the bodies, the GPU backend takes one body per lane (cuda/body_forces.cu).
// A body's sums run in its ascending triangle order on either.
#pragma once
#include <cmath>
#include <cstdint>

#include "common/host_device.hpp"

namespace engine {

struct BodyDragArrays {
  const double* x;
  const double* y;
  const double* vx;
  const double* vy;
  const double* body_area0;
  const int32_t* start;   // BodyTriangleLists: each body's places k (its triangles)
  const int32_t* corner;  // 3 per place: the triangle's nodes
  const double* weight;   // per place: the triangle's area0 / 3
  const int32_t* surface_start;  // and each body's surface points
  const int32_t* surface_node;
  double half_rho_cd;    // 1/2 rho_w C_d [kg/m³]
};

// The term of place k (a triangle) in its body's area-weighted velocity sum
// (centroid velocity times area).
ICERUBBLE_HD void drag_velocity_term(const BodyDragArrays& a, int32_t k, double& wx, double& wy) {
  const int32_t i0 = a.corner[3 * k], i1 = a.corner[3 * k + 1], i2 = a.corner[3 * k + 2];
  const double w = a.weight[k];
  wx = w * (a.vx[i0] + a.vx[i1] + a.vx[i2]);
  wy = w * (a.vy[i0] + a.vy[i1] + a.vy[i2]);
}

// c_b of body b from its velocity sums (Vx, Vy: the terms above summed) and
// the extent [lo, hi] of its corners along n = V-perp / |V| (see
// drag_direction); 0 for a body at rest.
ICERUBBLE_HD double drag_constant(double half_rho_cd, double speed, double lo, double hi) {
  return speed > 0.0 ? half_rho_cd * speed * (hi - lo) : 0.0;
}

// The mean velocity V of body b from its summed terms, its speed, and the
// unit normal n across it.
ICERUBBLE_HD double drag_direction(const BodyDragArrays& a, int32_t b, double& Vx, double& Vy,
                                   double& nx, double& ny) {
  if (a.body_area0[b] > 0.0) {
    Vx /= a.body_area0[b];
    Vy /= a.body_area0[b];
  }
  const double speed = hypot(Vx, Vy);
  nx = ny = 0.0;
  if (speed > 0.0) {
    nx = -Vy / speed;
    ny = Vx / speed;
  }
  return speed;
}

// Body b's c_b [N s/m per m width]: its mean velocity V (triangle centroids,
// area weighted, so shared bond nodes count for both bodies) and its width L
// across V (from its surface points: a body's extremes lie on its boundary);
// 0 for a body at rest. Sums in ascending triangle order.
ICERUBBLE_HD double quadratic_drag_constant(const BodyDragArrays& a, int32_t b) {
  double Vx = 0.0, Vy = 0.0;
  for (int32_t k = a.start[b]; k < a.start[b + 1]; ++k) {
    double wx, wy;
    drag_velocity_term(a, k, wx, wy);
    Vx += wx;
    Vy += wy;
  }
  double nx, ny;
  const double speed = drag_direction(a, b, Vx, Vy, nx, ny);
  if (!(speed > 0.0) || a.surface_start[b + 1] == a.surface_start[b]) return 0.0;
  // Width across the velocity: extent of the surface points along n.
  const int32_t first = a.surface_node[a.surface_start[b]];
  double lo = a.x[first] * nx + a.y[first] * ny, hi = lo;
  for (int32_t k = a.surface_start[b] + 1; k < a.surface_start[b + 1]; ++k) {
    const int32_t i = a.surface_node[k];
    const double s = a.x[i] * nx + a.y[i] * ny;
    // plain compares: fmin/fmax are library calls (NaN rules)
    if (s < lo) lo = s;
    if (s > hi) hi = s;
  }
  return drag_constant(a.half_rho_cd, speed, lo, hi);
}

}  // namespace engine
