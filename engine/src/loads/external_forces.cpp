#include "loads/external_forces.hpp"

#include <algorithm>
#include <cmath>

namespace engine {

Submerged submerged_part(double ax, double ay, double bx, double by, double cx, double cy,
                         double y_w) {
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

double water_forces_on_triangles(const Nodes& nodes, Triangles& tris, const ExternalParams& p,
                                 const std::vector<double>& body_area0,
                                 const std::vector<double>& body_drag, int32_t begin, int32_t end,
                                 const int32_t* list) {
  const double* x = nodes.x.data();
  const double* y = nodes.y.data();
  const int32_t* tn = tris.node.data();
  constexpr int s = CornerLoad::stride;
  double* load = tris.corner_load.data();
  const double weight = p.rho_w * p.g;
  double submerged = 0.0;
  for (int32_t k = begin; k < end; ++k) {
    const int32_t t = list ? list[k] : k;
    const int32_t i0 = tn[3 * t], i1 = tn[3 * t + 1], i2 = tn[3 * t + 2];
    const double ax = x[i0], ay = y[i0], bx = x[i1], by = y[i1], cx = x[i2], cy = y[i2];
    double* fb = load + 3 * s * t + CornerLoad::buoy_y;
    double* kd = load + 3 * s * t + CornerLoad::drag_k;
    fb[0] = fb[s] = fb[2 * s] = 0.0;
    kd[0] = kd[s] = kd[2 * s] = 0.0;
    if (ay >= p.y_w && by >= p.y_w && cy >= p.y_w) continue;
    const double area = 0.5 * ((bx - ax) * (cy - ay) - (cx - ax) * (by - ay));
    double l0 = 1.0 / 3.0, l1 = 1.0 / 3.0, l2 = 1.0 / 3.0, a_sub = area;
    if (!(ay < p.y_w && by < p.y_w && cy < p.y_w)) {
      const Submerged s = submerged_part(ax, ay, bx, by, cx, cy, p.y_w);
      a_sub = s.area;
      // Barycentric coordinates of the submerged centroid in the triangle.
      l1 = ((s.cx - ax) * (cy - ay) - (cx - ax) * (s.cy - ay)) / (2.0 * area);
      l2 = ((bx - ax) * (s.cy - ay) - (s.cx - ax) * (by - ay)) / (2.0 * area);
      l0 = 1.0 - l1 - l2;
    }
    submerged += a_sub;
    if (p.buoyancy) {
      const double fy = weight * a_sub;
      fb[0] = fy * l0;
      fb[s] = fy * l1;
      fb[2 * s] = fy * l2;
    }
    if (p.drag_on() && area > 0.0) {
      const int32_t b = tris.body[t];
      kd[0] = kd[s] = kd[2 * s] = body_drag[b] * (tris.area0[t] / body_area0[b]) * (a_sub / area) / 3.0;
    }
  }
  return submerged;
}

void BodyTriangleLists::build(const Triangles& tris, const std::vector<int32_t>& surface,
                              int32_t n_bodies) {
  const auto rows = [&](const int32_t* ids, int32_t n, std::vector<int32_t>& first, std::vector<int32_t>& out) {
    first.assign(size_t(n_bodies) + 1, 0);
    for (int32_t k = 0; k < n; ++k) ++first[tris.body[ids ? ids[k] : k] + 1];
    for (int32_t b = 0; b < n_bodies; ++b) first[b + 1] += first[b];
    out.resize(n);
    std::vector<int32_t> fill(first.begin(), first.end() - 1);
    for (int32_t k = 0; k < n; ++k) {
      const int32_t t = ids ? ids[k] : k;
      out[fill[tris.body[t]]++] = t;
    }
  };
  rows(nullptr, tris.size(), start, tri);
  rows(surface.data(), int32_t(surface.size()), surface_start, surface_tri);
}

void body_drag_constants(const Nodes& nodes, const Triangles& tris, const ExternalParams& p,
                         const std::vector<double>& body_area0, std::vector<double>& body_drag,
                         const BodyTriangleLists& lists, int threads) {
  const int32_t nb = int32_t(body_area0.size());
  body_drag.assign(nb, 0.0);
  if (!p.drag_on()) return;
  if (p.drag_model == DragModel::Linear) {
    std::fill(body_drag.begin(), body_drag.end(), p.c_w);
    return;
  }
  const int32_t* tn = tris.node.data();
  const double* vx = nodes.vx.data();
  const double* vy = nodes.vy.data();
  const double* x = nodes.x.data();
  const double* y = nodes.y.data();
  const double half_rho_cd = 0.5 * p.rho_w * p.C_d;
  // dynamic: the layer's bodies are far larger than a block
  #pragma omp parallel for schedule(dynamic, 8) num_threads(threads) if (threads > 1)
  for (int32_t b = 0; b < nb; ++b) {
    // Mean velocity (triangle centroids, area weighted).
    double Vx = 0.0, Vy = 0.0;
    for (int32_t k = lists.start[b]; k < lists.start[b + 1]; ++k) {
      const int32_t t = lists.tri[k];
      const int32_t i0 = tn[3 * t], i1 = tn[3 * t + 1], i2 = tn[3 * t + 2];
      const double w = tris.area0[t] / 3.0;
      Vx += w * (vx[i0] + vx[i1] + vx[i2]);
      Vy += w * (vy[i0] + vy[i1] + vy[i2]);
    }
    if (body_area0[b] > 0.0) {
      Vx /= body_area0[b];
      Vy /= body_area0[b];
    }
    const double speed = std::hypot(Vx, Vy);
    if (!(speed > 0.0)) continue;
    // Width across the velocity: extent of the corners along n = V-perp.
    const double nx = -Vy / speed, ny = Vx / speed;
    bool seen = false;
    double lo = 0.0, hi = 0.0;
    for (int32_t k = lists.surface_start[b]; k < lists.surface_start[b + 1]; ++k) {
      const int32_t t = lists.surface_tri[k];
      for (int c = 0; c < 3; ++c) {
        const int32_t i = tn[3 * t + c];
        const double s = x[i] * nx + y[i] * ny;
        if (!seen) {
          lo = hi = s;
          seen = true;
        } else {
          // plain compares: std::fmin/fmax are library calls (NaN rules)
          if (s < lo) lo = s;
          if (s > hi) hi = s;
        }
      }
    }
    if (seen) body_drag[b] = half_rho_cd * speed * (hi - lo);
  }
}

}  // namespace engine
