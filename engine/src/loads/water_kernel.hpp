// One triangle's water loads (docs/model.md §3.4), written once for both
// backends: water_forces_on_triangles (CPU) loops over it, the GPU backend
// launches it per triangle (cuda/body_forces.cu), with the CPU's arithmetic
// and order.
#pragma once
#include <cstdint>

#include "common/corner_layout.hpp"
#include "common/host_device.hpp"
#include "common/mesh_arrays.hpp"

namespace engine {

// Submerged area and centroid of a triangle below y_w.
struct Submerged {
  double area = 0.0, cx = 0.0, cy = 0.0;
};

ICERUBBLE_HD Submerged submerged_part(double ax, double ay, double bx, double by, double cx,
                                      double cy, double y_w) {
  const double px[3] = {ax, bx, cx}, py[3] = {ay, by, cy};
  Submerged s;
  if (ay >= y_w && by >= y_w && cy >= y_w) return s;
  // Clip the triangle with the half plane y <= y_w (at most 4 vertices).
  double qx[4], qy[4];
  int n = 0;
  for (int i = 0; i < 3; ++i) {
    const int j = (i + 1) % 3;
    const bool in_i = py[i] < y_w, in_j = py[j] < y_w;
    if (in_i) { qx[n] = px[i]; qy[n] = py[i]; ++n; }
    if (in_i != in_j) {
      const double s_ij = (y_w - py[i]) / (py[j] - py[i]);
      qx[n] = px[i] + s_ij * (px[j] - px[i]);
      qy[n] = y_w;
      ++n;
    }
  }
  // Shoelace area and centroid, relative to the first vertex for accuracy.
  double a2 = 0.0, sx = 0.0, sy = 0.0;
  for (int i = 1; i + 1 < n; ++i) {
    const double ux = qx[i] - qx[0], uy = qy[i] - qy[0];
    const double wx = qx[i + 1] - qx[0], wy = qy[i + 1] - qy[0];
    const double c = ux * wy - uy * wx;
    a2 += c;
    sx += c * (ux + wx);
    sy += c * (uy + wy);
  }
  if (!(a2 > 0.0)) return s;
  s.area = 0.5 * a2;
  s.cx = qx[0] + sx / (3.0 * a2);
  s.cy = qy[0] + sy / (3.0 * a2);
  return s;
}

// What the water pass reads and writes, as flat arrays (host or device).
struct WaterArrays {
  const double* x;
  const double* y;
  const int32_t* node;
  const int32_t* body;
  const double* area0;
  const double* body_area0;
  const double* body_drag;  // each body's drag constant c_b [N s/m per m width]
  double y_w;     // water line [m]
  double weight;  // rho_w g [N/m³]
  bool buoyancy, drag;
};

// Triangle t's buoyancy per corner (the submerged part's rho_w g A_sub at its
// centroid, shared barycentrically) and each corner's share of the drag
// coefficient, into `load` (common/corner_layout.hpp). Returns the submerged area.
template <class Corners>
ICERUBBLE_HD double water_triangle(const WaterArrays& a, Corners load, int32_t t) {
  const size_t s0 = 3 * size_t(t);
  constexpr int fb = CornerLoad::buoy_y, kd = CornerLoad::drag_k;
  const int32_t i0 = a.node[3 * t], i1 = a.node[3 * t + 1], i2 = a.node[3 * t + 2];
  const double ax = a.x[i0], ay = a.y[i0], bx = a.x[i1], by = a.y[i1], cx = a.x[i2], cy = a.y[i2];
  load(s0, fb) = load(s0 + 1, fb) = load(s0 + 2, fb) = 0.0;
  load(s0, kd) = load(s0 + 1, kd) = load(s0 + 2, kd) = 0.0;
  const double y_w = a.y_w;
  if (ay >= y_w && by >= y_w && cy >= y_w) return 0.0;
  const double area = 0.5 * ((bx - ax) * (cy - ay) - (cx - ax) * (by - ay));
  double l0 = 1.0 / 3.0, l1 = 1.0 / 3.0, l2 = 1.0 / 3.0, a_sub = area;
  if (!(ay < y_w && by < y_w && cy < y_w)) {
    const Submerged sub = submerged_part(ax, ay, bx, by, cx, cy, y_w);
    a_sub = sub.area;
    // Barycentric coordinates of the submerged centroid in the triangle.
    l1 = ((sub.cx - ax) * (cy - ay) - (cx - ax) * (sub.cy - ay)) / (2.0 * area);
    l2 = ((bx - ax) * (sub.cy - ay) - (sub.cx - ax) * (by - ay)) / (2.0 * area);
    l0 = 1.0 - l1 - l2;
  }
  if (a.buoyancy) {
    const double fy = a.weight * a_sub;
    load(s0, fb) = fy * l0;
    load(s0 + 1, fb) = fy * l1;
    load(s0 + 2, fb) = fy * l2;
  }
  if (a.drag && area > 0.0) {
    const int32_t b = a.body[t];
    load(s0, kd) = load(s0 + 1, kd) = load(s0 + 2, kd) =
        a.body_drag[b] * (a.area0[t] / a.body_area0[b]) * (a_sub / area) / 3.0;
  }
  return a_sub;
}

}  // namespace engine
