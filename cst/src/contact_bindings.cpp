// Python access to the contact module alone (pair kernel tests, diagnostics).
#include "bindings.hpp"
#include "contact.hpp"

namespace cst {
void bind_contact(pybind11::module_&) {}
}
