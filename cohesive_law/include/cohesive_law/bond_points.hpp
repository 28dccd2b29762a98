// Structure-of-arrays containers of bond points for hosts that do not keep their own
// arrays (the YADE rigid-block model, the Python binding, tests). The engine may as well
// keep its own arrays and call step_opened_bond / step_elastic_bond in its loop.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "cohesive_law/elastic_bond.hpp"
#include "cohesive_law/softening.hpp"

namespace cohesive_law {

// Opened bond points of the initially rigid law (the FEM-DEM engine's split nodes).
class OpenedBondPoints {
 public:
  explicit OpenedBondPoints(ForceDirection dir = ForceDirection::paper) : direction(dir) {}

  // f0: |f_c^0| (eq 8, or initial_effective_force for work_conjugate) [N/m];
  // G [J/m^2]; l [m]; beta = tau_cr/sigma_cr. delta_f from eq 12. Returns the index.
  std::size_t add(double f0, double G, double l, double beta);
  std::size_t size() const { return f0.size(); }
  bool broken(std::size_t i) const { return delta_m[i] >= delta_f[i]; }

  // Advance every bond point to the given openings (arrays of size()). Outputs may be
  // null except f_n, f_t. Throws std::invalid_argument on a non-finite opening
  // before touching any state.
  void step(const double* delta_n, const double* delta_t, double* f_n, double* f_t,
            double* dissipation, std::int8_t* failed_now);

  ForceDirection direction;
  std::vector<double> beta, f0, delta_f, delta_m;
  std::vector<std::int8_t> mode;  // FailureMode codes; none until fully broken
};

// Initially elastic bond points (rigid blocks), see elastic_bond.hpp.
class ElasticBondPoints {
 public:
  explicit ElasticBondPoints(ForceDirection dir = ForceDirection::paper) : direction(dir) {}

  // Validates the parameters and k > min_elastic_stiffness (tensile-side peaks).
  std::size_t add(const ElasticBondParams& p);
  std::size_t size() const { return params.size(); }

  // As OpenedBondPoints::step, plus initiated_now. Throws std::runtime_error naming the
  // first bond point whose peak (under compression) lies beyond delta_f; bond points
  // before it in the array have already been advanced (the run must stop anyway).
  void step(const double* delta_n, const double* delta_t, double* f_n, double* f_t,
            double* dissipation, std::int8_t* initiated_now, std::int8_t* failed_now);

  // Recoverable energy at the last opening stepped to: elastic (intact) or secant
  // (opened, see stored_energy in softening.hpp), 0 when broken.
  double stored_energy(std::size_t i) const;

  ForceDirection direction;
  std::vector<ElasticBondParams> params;
  std::vector<std::int8_t> state, mode;  // BondState and FailureMode codes
  std::vector<double> f0, delta_f, delta_m, delta_0;
  std::vector<double> peak_f_n, peak_f_t;  // elastic force at the peak (0 before it)
  std::vector<double> delta_n_prev, delta_t_prev;
};

}  // namespace cohesive_law
