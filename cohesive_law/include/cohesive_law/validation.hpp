// Parameter checks shared by the containers and the Python binding. They throw
// std::invalid_argument (ValueError in Python) naming the parameter and its valid range.
#pragma once

#include <string>

#include "cohesive_law/softening.hpp"

namespace cohesive_law {

void require_positive(const char* name, double value);      // value > 0 and finite
void require_non_negative(const char* name, double value);  // value >= 0 and finite
void require_finite(const char* name, double value);
ForceDirection parse_direction(const std::string& name);    // "paper" | "work_conjugate"
const char* direction_name(ForceDirection dir);
// sigma_cr > 0, tau_cr > 0, mu >= 0
void validate_strength(double sigma_cr, double tau_cr, double mu);
// 0 < keel_depth, 0 < bottom_fraction <= 1
void validate_depth_scaling(double keel_depth, double bottom_fraction);

}  // namespace cohesive_law
