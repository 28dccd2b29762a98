// Kinematic boundary conditions on node sets: fixed nodes and prescribed
// velocity histories (the displacement-driven indenter, docs/model.md §1), and the
// reaction the boundary exerts to impose them.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

namespace engine {

// Smooth ramp s = v_f (t/T - sin(2 pi t/T)/(2 pi)) for 0 < t < T, 0 before,
// v_f after: the acceleration rises from zero and returns to zero at T, so
// the indenter starts without a jerk. Python: _engine.ramp_velocity.
double ramp_velocity(double time, double v_final, double ramp_time);

// Scalar speed s(t) [m/s]; the node velocity is direction * s(t).
struct VelocityHistory {
  enum class Kind { constant, smooth_ramp, table };
  Kind kind = Kind::constant;
  double value = 0.0;      // constant: s; smooth_ramp: final speed
  double ramp_time = 0.0;  // smooth_ramp: time to reach the final speed [s]
  std::vector<double> t, v;  // table: piecewise linear, held constant outside

  double at(double time) const;
  // Throws std::invalid_argument naming the bad parameter.
  void validate(const std::string& where) const;
};

struct BoundaryCondition {
  std::string name;
  std::vector<int32_t> nodes;
  bool x = true, y = true;  // which velocity components are prescribed
  double dir_x = 0.0, dir_y = 0.0;
  VelocityHistory history;  // fixed nodes: constant 0
};

}  // namespace engine
