// Each part of the engine registers its Python API in its own *_bindings.cpp.
#pragma once
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <vector>

namespace engine {

// A numpy copy of an engine array (every part's bindings hand arrays out so).
template <class T>
pybind11::array_t<T> as_array(const std::vector<T>& v) {
  return pybind11::array_t<T>(pybind11::ssize_t(v.size()), v.data());
}

void bind_contact(pybind11::module_& m);
void bind_model(pybind11::module_& m);
void bind_freeze_bonds(pybind11::module_& m);  // after bind_model: adds to Model
void bind_loads(pybind11::module_& m);
void bind_rigid(pybind11::module_& m);  // rigid-block water law (discrete-only model)
void bind_device(pybind11::module_& m);  // the GPU backend (cuda/)
}
