// The contact reach guard's test of one node (Model::guard_contact_reach),
// written once for both backends: the CPU loops over the nodes, the GPU's
// whole step takes a node per lane (cuda/device_step.cu).
#pragma once
#include "common/host_device.hpp"

namespace engine {

// Whether a node at (x, y) has moved more than `half` (half the contact
// reach) from (x0, y0), where it was when the contact step was last bound.
ICERUBBLE_HD bool moved_past_reach(double x, double y, double x0, double y0, double half) {
  const double dx = x - x0, dy = y - y0;
  return dx * dx + dy * dy > half * half;
}

}  // namespace engine
