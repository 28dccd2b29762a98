// The one check of the engine's parameters, against the registry's ranges
// (engine_parameter_ranges.hpp, written by the build from
// icerubble/parameters.py); each part checks its own (contact, loads, sleeping).
#include "model/engine_parameters.hpp"

#include "common/parameter_range.hpp"
#include "engine_parameter_ranges.hpp"

namespace engine {

void validate(const EngineParameters& p) {
  validate(p.external);
  validate(p.contact);
  validate(p.sleep);
  check(registry::energy_tolerance, p.energy_tolerance);
  check(registry::local_damping, p.local_damping);
  check(registry::mass_scaling_dt, p.mass_scaling_dt);
  check(registry::contact_reach, p.contact_reach);
  check(registry::threads, double(p.threads));
}

}  // namespace engine
