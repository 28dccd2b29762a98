#include "cohesive_law/freeze_bond.hpp"

namespace cohesive_law {
const char* version() { return "0.2"; }
}
