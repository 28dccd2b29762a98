// Every parameter the FEM-DEM engine reads, in one struct that crosses the
// binding whole (issue 27). Their defaults, units and ranges are declared
// once, in icerubble/parameters.py (the registry's engine=True entries): the
// Python wrapper (icerubble/engine/model.py) sends a full struct of the
// registry's values, and Model::set_parameters checks it here, once, against
// the registry's ranges, which the build writes into
// engine_parameter_ranges.hpp. No default lives in C++: a number not given is
// NaN, which the check refuses, and a model runs only once it has been given
// a struct.
#pragma once
#include <cstdint>

#include "contact/contact.hpp"
#include "loads/external_forces.hpp"
#include "model/sleeping.hpp"

namespace engine {

struct EngineParameters {
  ExternalParams external;       // gravity, buoyancy, drag: g, rho_w, y_w, c_w, drag_model, C_d
  ContactParams contact;         // penalty, mu
  SleepParams sleep;             // the sleeping far field
  bool check_stable_dt = true;   // refuse a dt above the stable step
  bool check_energy = true;      // stop when energy grows without a source
  double energy_tolerance = NAN; // of the energy balance residual [-]
  double local_damping = NAN;    // Cundall's alpha, for reaching rest [-]
  double mass_scaling_dt = NAN;  // selective mass scaling's target step, 0: off [s]
  double contact_reach = NAN;    // the contact stable step's reach, inf: the whole mesh [m]
  int32_t threads = -1;          // OpenMP threads, 0: OpenMP's default
};

// Throws std::invalid_argument naming the first parameter out of its
// registry range (and the range).
void validate(const EngineParameters& p);

}  // namespace engine
