// Freeze-bond cohesive law (Polojärvi & Tuhkuri 2013, eqs 5-12): one include for all.
//   criterion.hpp      eqs 5-6, effective traction and failure criterion
//   softening.hpp      eqs 8-12, one opened bond point (scalar, inlinable)
//   elastic_bond.hpp   initially elastic variant for rigid blocks
//   depth_scaling.hpp  strength and G versus depth in the keel
//   bond_points.hpp    structure-of-arrays containers
//   validation.hpp     parameter checks
#pragma once

#include "cohesive_law/bond_points.hpp"
#include "cohesive_law/criterion.hpp"
#include "cohesive_law/depth_scaling.hpp"
#include "cohesive_law/elastic_bond.hpp"
#include "cohesive_law/softening.hpp"
#include "cohesive_law/validation.hpp"

namespace cohesive_law {
const char* version();
}
