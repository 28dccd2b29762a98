// The engine's parameters where they enter: validated once, here at the
// boundary, against the registry's ranges (engine_parameter_ranges.hpp);
// nothing is re-checked per step.
#include "common/input_errors.hpp"
#include "common/parameter_range.hpp"
#include "engine_parameter_ranges.hpp"
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
  check(registry::dt, dt);
  dt_ = dt;
  dt_fraction_ = 0.0;
}

void Model::set_dt_fraction(double f) {
  // (0, 1]: the stable step already carries its safety factor
  check(registry::dt_fraction, f);
  dt_ = f * stable_step().dt;
  dt_fraction_ = f;
}

namespace {

// (before the first struct the old values are NaN, unequal to any: all changed)
bool same_water(const ExternalParams& a, const ExternalParams& b) {
  return a.buoyancy == b.buoyancy && a.drag == b.drag && a.rho_w == b.rho_w && a.y_w == b.y_w &&
         a.c_w == b.c_w && a.drag_model == b.drag_model && a.C_d == b.C_d;
}

}  // namespace

void Model::set_parameters(const EngineParameters& p) {
  validate(p);
  const EngineParameters old = params_;
  params_ = p;
  parameters_set_ = true;
  // what a changed value makes stale: the stable step (water: the drag
  // limit; contact: the penalty limit), the masses (the contact part of the
  // mass scaling, the reach), the sleeping state (new thresholds apply to
  // the nodes as they are)
  if (!same_water(old.external, p.external)) stable_current_ = false;
  if (old.contact.penalty != p.contact.penalty || old.contact.mu != p.contact.mu) {
    stable_current_ = false;
    if (p.mass_scaling_dt > 0.0) prepared_ = false;
  }
  if (old.mass_scaling_dt != p.mass_scaling_dt) {
    prepared_ = false;
    stable_current_ = false;
  }
  if (old.contact_reach != p.contact_reach) prepared_ = false;
  if (old.sleep.on != p.sleep.on) wake_all();
}

void Model::require_parameters() const {
  if (!parameters_set_)
    bad("the engine's parameters are not set: Model.set_parameters({...}) with every engine parameter "
        "of icerubble/parameters.py first (icerubble.engine.Model does so with the registry's defaults)");
}

}  // namespace engine
