#include "loads/boundary_conditions.hpp"

#include <cmath>
#include <stdexcept>

namespace engine {

double ramp_velocity(double time, double v_final, double ramp_time) {
  if (time <= 0.0) return 0.0;
  if (time >= ramp_time) return v_final;
  const double s = time / ramp_time;
  return v_final * (s - std::sin(2.0 * M_PI * s) / (2.0 * M_PI));
}

double VelocityHistory::at(double time) const {
  switch (kind) {
    case Kind::constant:
      return value;
    case Kind::smooth_ramp:
      return ramp_velocity(time, value, ramp_time);
    case Kind::table: {
      if (time <= t.front()) return v.front();
      if (time >= t.back()) return v.back();
      size_t lo = 0, hi = t.size() - 1;  // bisection: t[lo] <= time < t[hi]
      while (hi - lo > 1) {
        const size_t mid = (lo + hi) / 2;
        (t[mid] <= time ? lo : hi) = mid;
      }
      const double w = (time - t[lo]) / (t[hi] - t[lo]);
      return v[lo] + w * (v[hi] - v[lo]);
    }
  }
  return 0.0;
}

void VelocityHistory::validate(const std::string& where) const {
  auto bad = [&](const std::string& msg) { throw std::invalid_argument(where + ": " + msg); };
  if (!std::isfinite(value)) bad("v_final must be finite");
  if (kind == Kind::smooth_ramp && !(ramp_time > 0.0 && std::isfinite(ramp_time)))
    bad("ramp_time must be > 0 s and finite (got " + std::to_string(ramp_time) + ")");
  if (kind == Kind::table) {
    if (t.empty() || t.size() != v.size())
      bad("table needs matching, non-empty time and velocity columns");
    for (size_t i = 0; i < t.size(); ++i) {
      if (!std::isfinite(t[i]) || !std::isfinite(v[i])) bad("table values must be finite");
      if (i > 0 && !(t[i] > t[i - 1])) bad("table times must be strictly increasing");
    }
  }
}

}  // namespace engine
