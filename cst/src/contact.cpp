// Placeholder until the potential contact module lands: no contact forces.
#include "contact.hpp"

namespace cst {

int32_t ContactSolver::compute_normal(const ContactParams&, const ContactInput&, double*, double*) {
  n_touching_ = 0;
  stored_energy_ = 0.0;
  return 0;
}

double ContactSolver::apply_friction(const ContactParams&, const ContactInput&, double*, double*) {
  return 0.0;
}

}  // namespace cst
