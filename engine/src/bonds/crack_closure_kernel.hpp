// One split pair's crack-closure force (why it exists:
// FreezeBonds::apply), written once for both backends: the CPU
// loops over the split pairs, the GPU's whole step takes a node per lane and
// its pairs in the CPU's order (cuda/cohesive_forces.cu).
#pragma once
#include <cstdint>

#include "common/host_device.hpp"

namespace engine {

// Whether pair (ip, im), its normal (nx, ny) frozen at the split, has closed
// past contact (x+ behind x- along the normal); then f [N/m], the penalty
// k's push on x+ along +n (x- takes the opposite).
ICERUBBLE_HD bool crack_closure_force(const double* x, const double* y, int32_t ip, int32_t im, double nx, double ny,
                                      double k, double& f) {
  const double delta_n = (x[ip] - x[im]) * nx + (y[ip] - y[im]) * ny;
  if (delta_n >= 0.0) return false;
  f = -k * delta_n;
  return true;
}

}  // namespace engine
