#include "rigid/rigid_friction.hpp"

#include "common/input_errors.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace engine {

void rigid_friction(const RigidContacts& c, const RigidBodies& B, double dt, double k_t, double mu,
                    FrictionHistory& history, double* ft, double* fx, double* fy, double* tz) {
  std::fill(fx, fx + B.n, 0.0);
  std::fill(fy, fy + B.n, 0.0);
  std::fill(tz, tz + B.n, 0.0);
  std::vector<int32_t> order(c.n);
  std::iota(order.begin(), order.end(), 0);
  const auto key = [&](int32_t k) { return friction_key(c.a[k], c.b[k]); };
  std::sort(order.begin(), order.end(), [&](int32_t i, int32_t j) { return key(i) < key(j); });
  FrictionHistory next;
  next.key.reserve(c.n);
  next.ft.reserve(c.n);
  size_t h = 0;  // walks the old history alongside (both ascending)
  for (const int32_t& k : order) {
    const uint64_t kk = key(k);
    while (h < history.key.size() && history.key[h] < kk) ++h;
    double f = (h < history.key.size() && history.key[h] == kk) ? history.ft[h] : 0.0;
    const int32_t a = c.a[k], b = c.b[k];
    const double tx = -c.ny[k], ty = c.nx[k];
    // velocities of the two bodies at the contact point
    const double rax = c.px[k] - B.x[a], ray = c.py[k] - B.y[a];
    const double rbx = c.px[k] - B.x[b], rby = c.py[k] - B.y[b];
    const double vax = B.vx[a] - B.omega[a] * ray, vay = B.vy[a] + B.omega[a] * rax;
    const double vbx = B.vx[b] - B.omega[b] * rby, vby = B.vy[b] + B.omega[b] * rbx;
    const double slip = (vbx - vax) * tx + (vby - vay) * ty;  // b relative to a, along t
    f -= k_t * slip * dt;
    const double cap = mu * std::max(c.fn[k], 0.0);
    const bool sticks = std::binary_search(history.stuck.begin(), history.stuck.end(), kk);
    if (!sticks && std::fabs(f) > cap) f = std::copysign(cap, f);
    ft[k] = f;
    if (!next.key.empty() && next.key.back() == kk)
      bad("contacts " + std::to_string(order[&k - order.data() - 1]) + " and " + std::to_string(k) +
          " are the same body pair (" + std::to_string(a) + ", " + std::to_string(b) +
          "): one contact per pair (a clump's pieces are bodies of their own)");
    next.key.push_back(kk);
    next.ft.push_back(f);
    const double Fx = f * tx, Fy = f * ty;  // on b; -F on a
    fx[b] += Fx;
    fy[b] += Fy;
    tz[b] += rbx * Fy - rby * Fx;
    fx[a] -= Fx;
    fy[a] -= Fy;
    tz[a] -= rax * Fy - ray * Fx;
  }
  next.stuck = std::move(history.stuck);
  history = std::move(next);
}

}  // namespace engine
