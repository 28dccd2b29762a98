#include "cohesive_law/validation.hpp"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace cohesive_law {

namespace {
[[noreturn]] void fail(const char* name, const char* range, double value) {
  std::ostringstream s;
  s << name << " must be " << range << " (got " << value << ")";
  throw std::invalid_argument(s.str());
}
}  // namespace

void require_positive(const char* name, double value) {
  if (!(std::isfinite(value) && value > 0.0)) fail(name, "finite and > 0", value);
}

void require_non_negative(const char* name, double value) {
  if (!(std::isfinite(value) && value >= 0.0)) fail(name, "finite and >= 0", value);
}

void require_finite(const char* name, double value) {
  if (!std::isfinite(value)) fail(name, "finite", value);
}

ForceDirection parse_direction(const std::string& name) {
  if (name == "paper") return ForceDirection::paper;
  if (name == "work_conjugate") return ForceDirection::work_conjugate;
  throw std::invalid_argument("direction must be 'paper' (eq 11 as printed) or "
                              "'work_conjugate' (Ortiz & Pandolfi 1999), got '" + name + "'");
}

const char* direction_name(ForceDirection dir) {
  return dir == ForceDirection::paper ? "paper" : "work_conjugate";
}

void validate_strength(double sigma_cr, double tau_cr, double mu) {
  require_positive("sigma_cr", sigma_cr);
  require_positive("tau_cr", tau_cr);
  require_non_negative("mu", mu);
}

void validate_depth_scaling(double keel_depth, double bottom_fraction) {
  require_positive("keel_depth", keel_depth);
  if (!(bottom_fraction > 0.0 && bottom_fraction <= 1.0))
    fail("bottom_fraction", "in (0, 1]", bottom_fraction);
}

}  // namespace cohesive_law
