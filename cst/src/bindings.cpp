#include "bindings.hpp"

PYBIND11_MODULE(_cst, m) {
  m.doc() = "CST FEM-DEM engine: deformable blocks, potential contact, freeze bonds";
  m.def("version", []() { return "0.1"; });
  cst::bind_contact(m);
  cst::bind_model(m);
  cst::bind_freeze_bonds(m);
}
