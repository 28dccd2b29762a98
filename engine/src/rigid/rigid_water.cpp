#include "rigid/rigid_water.hpp"

#include <cmath>
#include <vector>

namespace engine {

// Clip against y < y_w (Sutherland-Hodgman: one half plane keeps a simple
// polygon's area exact, degenerate bridges along the cut add none), then
// triangle-fan moments about the origin (ox, oy).
SubmergedMoments submerged_moments(const double* px, const double* py, int32_t n, double y_w,
                                   double ox, double oy) {
  SubmergedMoments m;
  std::vector<double> qx, qy;
  qx.reserve(2 * size_t(n));
  qy.reserve(2 * size_t(n));
  for (int32_t i = 0; i < n; ++i) {
    const int32_t j = (i + 1) % n;
    const bool in_i = py[i] < y_w, in_j = py[j] < y_w;
    if (in_i) {
      qx.push_back(px[i] - ox);
      qy.push_back(py[i] - oy);
    }
    if (in_i != in_j) {
      const double s = (y_w - py[i]) / (py[j] - py[i]);
      qx.push_back(px[i] + s * (px[j] - px[i]) - ox);
      qy.push_back(y_w - oy);
    }
  }
  const size_t k = qx.size();
  for (size_t i = 0; i < k; ++i) {
    // triangle (origin, q_i, q_{i+1}): exact polygon moments by Green's theorem
    const size_t j = (i + 1) % k;
    const double x0 = qx[i], y0 = qy[i], x1 = qx[j], y1 = qy[j];
    const double c = x0 * y1 - x1 * y0;
    m.area += 0.5 * c;
    m.sx += c * (x0 + x1) / 6.0;
    m.sy += c * (y0 + y1) / 6.0;
    m.polar += c * (x0 * x0 + x0 * x1 + x1 * x1 + y0 * y0 + y0 * y1 + y1 * y1) / 12.0;
  }
  return m;
}

void rigid_water_forces(const RigidBlocks& b, const ExternalParams& p, double* fx, double* fy,
                        double* tz, int threads) {
  const double weight = p.rho_w * p.g;
  #pragma omp parallel for schedule(dynamic, 16) num_threads(threads) if (threads > 1)
  for (int32_t k = 0; k < b.n; ++k) {
    fx[k] = fy[k] = tz[k] = 0.0;
    const int32_t c0 = b.offset[k], n = b.offset[k + 1] - c0;
    const double cs = std::cos(b.theta[k]), sn = std::sin(b.theta[k]);
    std::vector<double> px(n), py(n);
    double ymin = INFINITY;
    for (int32_t i = 0; i < n; ++i) {
      px[i] = b.cx[k] + cs * b.vx[c0 + i] - sn * b.vy[c0 + i];
      py[i] = b.cy[k] + sn * b.vx[c0 + i] + cs * b.vy[c0 + i];
      ymin = std::fmin(ymin, py[i]);
    }
    if (!(ymin < p.y_w)) continue;  // dry
    const SubmergedMoments s = submerged_moments(px.data(), py.data(), n, p.y_w, b.cx[k], b.cy[k]);
    if (!(s.area > 0.0)) continue;
    if (p.buoyancy) {
      const double F = weight * s.area;
      fy[k] += F;
      tz[k] += (s.sx / s.area) * F;  // (c_s - c) x (0, F)
    }
    if (!p.drag_on()) continue;
    const double Vx = b.ux[k], Vy = b.uy[k], w = b.omega[k];
    double c_b = p.c_w;
    if (p.drag_model == DragModel::Quadratic) {
      const double speed = std::hypot(Vx, Vy);
      if (!(speed > 0.0)) {
        c_b = 0.0;
      } else {
        const double nx = -Vy / speed, ny = Vx / speed;  // across V
        double lo = INFINITY, hi = -INFINITY;
        for (int32_t i = 0; i < n; ++i) {
          const double t = px[i] * nx + py[i] * ny;
          if (t < lo) lo = t;
          if (t > hi) hi = t;
        }
        c_b = 0.5 * p.rho_w * p.C_d * speed * (hi - lo);
      }
    }
    const double a = c_b / b.area[k];
    // F_d = -a (A_s V + w z x S), S = (sx, sy) the submerged first moment about c
    fx[k] += -a * (s.area * Vx - w * s.sy);
    fy[k] += -a * (s.area * Vy + w * s.sx);
    tz[k] += -a * ((s.sx * Vy - s.sy * Vx) + w * s.polar);
  }
}

}  // namespace engine
