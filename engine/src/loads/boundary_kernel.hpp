// One node's kinematic boundary condition (loads/boundary_conditions.hpp),
// written once for both backends: Model::apply_boundary_conditions loops over
// a condition's nodes, the GPU step launches it per node (cuda/device_step.cu).
// The boundary adds r = m (v_bc - v)/dt - f, so that the update lands exactly
// on the prescribed velocity; r is what the boundary pushes with.
#pragma once
#include <cstdint>

#include "common/host_device.hpp"

namespace engine {

// Component arrays of one direction (x or y) of the node state.
struct BoundaryComponent {
  const double* mass;
  const double* v;   // velocity at t - dt/2
  const double* f;   // every other force of the step
  double* v_bc;      // the prescribed velocity
  double* r;         // the reaction
};

ICERUBBLE_HD void prescribe_component(const BoundaryComponent& a, int32_t i, double v_bc, double inv_dt) {
  a.v_bc[i] = v_bc;
  a.r[i] = a.mass[i] * (v_bc - a.v[i]) * inv_dt - a.f[i];
}

}  // namespace engine
