#include "model/energy.hpp"

#include <cmath>

namespace engine {

double EnergyLedger::scale() const {
  return std::fabs(kinetic) + std::fabs(elastic_midstep) + std::fabs(contact) +
         std::fabs(friction) + std::fabs(damping) + std::fabs(drag) + std::fabs(cohesive) + std::fabs(cohesive_stored) +
         std::fabs(work_gravity) + std::fabs(work_buoyancy) + std::fabs(work_boundary) +
         std::fabs(initial);
}

}  // namespace engine
