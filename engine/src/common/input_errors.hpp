// Clear errors for bad input: std::invalid_argument (Python ValueError) with
// numbers printed the same way everywhere in the engine.
#pragma once
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

namespace engine {

inline std::string num(double v) {
  std::ostringstream o;
  o.precision(6);
  o << v;
  return o.str();
}

// Every digit of a double: for comparisons that differ in the last places.
inline std::string num17(double v) {
  std::ostringstream o;
  o.precision(17);
  o << v;
  return o.str();
}

[[noreturn]] inline void bad(const std::string& msg) { throw std::invalid_argument(msg); }

inline void require_finite_positive(const char* name, double v, const char* unit) {
  if (!(v > 0.0) || !std::isfinite(v))
    bad(std::string(name) + " must be > 0 " + unit + " and finite (got " + num(v) + ")");
}

inline void require_finite_nonnegative(const char* name, double v, const char* unit) {
  if (!(v >= 0.0) || !std::isfinite(v))
    bad(std::string(name) + " must be >= 0 " + unit + " and finite (got " + num(v) + ")");
}

}  // namespace engine
