// Depth dependence of the freeze-bond parameters (docs/model.md §2): sigma_cr, tau_cr and G
// fall linearly from their value at the keel top (depth 0) to bottom_fraction of it at
// the keel bottom (depth = keel_depth); outside the keel the nearest end value holds.
// beta = tau_cr / sigma_cr is therefore the same at every depth.
#pragma once

namespace cohesive_law {

inline double depth_factor(double depth, double keel_depth, double bottom_fraction = 0.1) {
  double z = depth / keel_depth;
  z = z < 0.0 ? 0.0 : (z > 1.0 ? 1.0 : z);
  return 1.0 - (1.0 - bottom_fraction) * z;
}

}  // namespace cohesive_law
