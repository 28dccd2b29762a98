#include "bindings/bindings.hpp"

PYBIND11_MODULE(_engine, m) {
  m.doc() = "CST FEM-DEM engine: deformable blocks, potential contact, freeze bonds";
  m.def("version", []() { return "0.1"; });
  // the compile flags decide the rounding of every result: recorded with it
  m.attr("build") = ICERUBBLE_BUILD;
  engine::bind_contact(m);
  engine::bind_model(m);
  engine::bind_freeze_bonds(m);
  engine::bind_loads(m);
  engine::bind_rigid(m);
  engine::bind_device(m);
}
