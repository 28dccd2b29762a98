// Parameter setters: each validates its value once, here at the boundary,
// and names the valid range; nothing is re-checked per step.
#include "common/input_errors.hpp"
#include "model/model.hpp"

#include <cmath>

namespace engine {

void Model::set_material(int32_t b, const Material& mat) {
  if (b < 0 || b >= n_bodies())
    bad("body must be in [0, " + std::to_string(n_bodies() - 1) + "] (got " + std::to_string(b) + ")");
  require_finite_positive("E", mat.E, "Pa");
  if (!(mat.nu >= 0.0 && mat.nu < 0.5)) bad("nu must be in [0, 0.5) (got " + num(mat.nu) + ")");
  require_finite_positive("rho", mat.rho, "kg/m³");
  require_finite_nonnegative("damping", mat.damping, "s");
  require_finite_nonnegative("viscosity", mat.viscosity, "Pa s");
  materials_[b] = mat;
  materials_[b].set = true;
  prepared_ = false;
  stable_current_ = false;
}

void Model::set_dt(double dt) {
  require_finite_positive("dt", dt, "s");
  dt_ = dt;
  dt_fraction_ = 0.0;
}

void Model::set_dt_fraction(double f) {
  if (!(f > 0.0 && f <= 1.0))
    bad("dt_fraction must be in (0, 1] (the stable step already carries its safety factor) (got " +
        num(f) + ")");
  dt_ = f * stable_step().dt;
  dt_fraction_ = f;
}

void Model::set_gravity(bool on, double g) {
  require_finite_nonnegative("g", g, "m/s²");
  ext_.gravity = on;
  ext_.g = g;
}

void Model::set_water(bool buoyancy, bool drag, double rho_w, double y_w, double c_w) {
  require_finite_nonnegative("rho_w", rho_w, "kg/m³");
  require_finite_nonnegative("c_w", c_w, "Pa s");
  if (!std::isfinite(y_w)) bad("y_w (water line) must be finite (got " + num(y_w) + ")");
  ext_.buoyancy = buoyancy;
  ext_.drag = drag;
  ext_.rho_w = rho_w;
  ext_.y_w = y_w;
  ext_.c_w = c_w;
  stable_current_ = false;
}

void Model::set_drag_model(DragModel model, double C_d) {
  require_finite_nonnegative("C_d", C_d, "");
  ext_.drag_model = model;
  ext_.C_d = C_d;
  stable_current_ = false;
}

void Model::set_contact(double penalty, double mu) {
  contact_params_ = validated_contact_params(penalty, mu);
  stable_current_ = false;
  // The contact part of mass scaling depends on the penalty.
  if (mass_scaling_dt_ > 0.0) prepared_ = false;
}

void Model::set_local_damping(double alpha) {
  if (!(alpha >= 0.0 && alpha < 1.0))
    throw std::invalid_argument("local_damping = " + std::to_string(alpha) + " is out of range: valid range [0, 1)");
  local_damping_ = alpha;
}

void Model::set_energy_tolerance(double tol) { require_finite_positive("energy_tolerance", tol, ""); energy_tolerance_ = tol; }

void Model::set_mass_scaling(double dt_target) {
  require_finite_nonnegative("mass_scaling_dt", dt_target, "s (0: off)");
  mass_scaling_dt_ = dt_target;
  prepared_ = false;  // masses change
  stable_current_ = false;
}

void Model::set_threads(int n) {
  if (n < 0) bad("threads must be >= 0 (0: OpenMP default)");
  threads_ = n;
}

void Model::set_contact_reach(double reach) {
  if (!(reach > 0.0)) bad("contact_reach must be > 0 m (infinite: the whole mesh) (got " + num(reach) + ")");
  contact_reach_ = reach;
  prepared_ = false;  // the mass scaling and the stable step depend on it
}

}  // namespace engine
