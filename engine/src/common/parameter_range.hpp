// A parameter's valid range as the registry declares it (icerubble/parameters.py;
// the build writes each engine parameter's as a ParameterRange into
// engine_parameter_ranges.hpp), and the one check of a value against it, with
// the message the registry's own check (parameters.check_value) gives.
#pragma once
#include <cmath>
#include <string>

#include "common/input_errors.hpp"

namespace engine {

struct ParameterRange {
  const char* name;
  const char* unit;
  double lo, hi;
  bool has_lo, has_hi;
  bool lo_open, hi_open;
  bool inf_ok;        // +inf is a value (contact_reach: the whole mesh)
  bool whole;         // a whole number (threads, sleep_quiet_steps)
  const char* range_text;   // '[0.0, inf)', 'a whole number >= 1', ...
  const char* rule_text;    // '>= 0, finite', ...
};

inline bool in_range(const ParameterRange& r, double v) {
  bool ok = std::isfinite(v) || (r.inf_ok && v == INFINITY);
  if (r.has_lo) ok = ok && v >= r.lo && !(r.lo_open && v == r.lo);
  if (r.has_hi) ok = ok && v <= r.hi && !(r.hi_open && v == r.hi);
  if (r.whole) ok = ok && v == std::floor(v);
  return ok;
}

// Throws std::invalid_argument (ValueError in Python) naming the parameter,
// the value and the valid range.
inline void check(const ParameterRange& r, double v) {
  if (in_range(r, v)) return;
  if (r.whole) bad(std::string(r.name) + "=" + num(v) + " must be " + r.range_text);
  bad(std::string("parameter ") + r.name + "=" + num(v) + " is out of range: valid range " + r.range_text + " " +
      r.unit + " (" + r.rule_text + ")");
}

}  // namespace engine
