#include <pybind11/pybind11.h>
#include "cohesive_law/freeze_bond.hpp"

PYBIND11_MODULE(_cohesive_law, m) {
  m.doc() = "Freeze-bond cohesive law (mixed-mode criterion, linear softening)";
  m.def("version", &cohesive_law::version);
}
