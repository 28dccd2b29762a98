// Python access to the freeze bonds of a Model (wrapped by icerubble/engine/model.py:
// Model.set_bond_points, Model.bonds, checkpoints). Adds methods to the Model
// class registered by model_bindings.cpp.
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <cmath>
#include <type_traits>

#include "bindings/bindings.hpp"
#include "cohesive_law/validation.hpp"
#include "model/model.hpp"

namespace py = pybind11;

namespace engine {

namespace {

template <class T>
std::vector<T> vec(const py::handle& h) {
  auto a = py::array_t<T, py::array::c_style | py::array::forcecast>::ensure(h);
  if (!a) throw std::invalid_argument("expected a numeric array");
  if (a.ndim() != 1) throw std::invalid_argument("expected a 1-D array");
  return std::vector<T>(a.data(), a.data() + a.size());
}


template <class T, bool = std::is_enum_v<T>>
struct StoredAs { using type = T; };
template <class T>
struct StoredAs<T, true> { using type = std::underlying_type_t<T>; };
// How a field's values travel to and from numpy: enums as their codes.
template <class T>
using Stored = typename StoredAs<T>::type;

// A field to Python: arrays as numpy arrays of the stored codes (enums as
// their underlying integers), totals as numbers.
template <class Field>
py::object to_py(const Field& f) {
  if constexpr (is_bond_array<Field>) {
    using T = typename Field::value_type;
    py::array_t<Stored<T>> a(f.size());
    std::transform(f.begin(), f.end(), a.mutable_data(), [](T v) { return Stored<T>(v); });
    return std::move(a);
  } else {
    return py::cast(f);
  }
}

template <class Field>
void from_py(const py::handle& h, Field& f) {
  if constexpr (is_bond_array<Field>) {
    using T = typename Field::value_type;
    const std::vector<Stored<T>> v = vec<Stored<T>>(h);
    f.resize(v.size());
    std::transform(v.begin(), v.end(), f.begin(), [](Stored<T> x) { return T(x); });
  } else {
    f = h.cast<Field>();
  }
}

template <class S>
py::dict to_dict(const S& s) {
  py::dict d;
  S::each(s, [&](const char* key, BondExtent, const auto& field, auto) { d[key] = to_py(field); });
  return d;
}

template <class S>
S from_dict(const py::dict& d, const char* what) {
  S s;
  S::each(s, [&](const char* key, BondExtent, auto& field, auto) {
    if (!d.contains(key)) throw std::invalid_argument(std::string(what) + " lacks '" + key + "'");
    from_py(d[key], field);
  });
  return s;
}

}  // namespace

void bind_freeze_bonds(py::module_& m) {
  // The codes of the int8 arrays bond_state() returns: point_state, pair_state, mode.
  py::enum_<PointState>(m, "PointState", "bond_state()['point_state'] codes")
      .value("intact", PointState::intact)
      .value("split", PointState::split);
  py::enum_<PairState>(m, "PairState", "bond_state()['pair_state'] codes")
      .value("intact", PairState::intact)
      .value("cohesive", PairState::cohesive, "split, held by the cohesive law")
      .value("failed", PairState::failed, "fully failed");
  py::enum_<FailureMode>(m, "FailureMode", "bond_state()['mode'] codes", py::module_local())
      .value("none", FailureMode::none)
      .value("tensile", FailureMode::tensile)
      .value("shear", FailureMode::shear);
  auto cls = py::reinterpret_borrow<py::class_<Model>>(py::type::of<Model>());
  cls.def("set_bonds",
          [](Model& M, py::args arrays, bool for_restore) {
            BondInput in;
            size_t i = 0;
            BondInput::each(in, [&](const char* key, BondExtent, auto& field, auto) {
              if (i >= arrays.size())
                throw std::invalid_argument(std::string("set_bonds: missing array '") + key +
                                            "' (the arrays come in bond_input() key order)");
              from_py(arrays[i++], field);
            });
            if (i != arrays.size())
              throw std::invalid_argument("set_bonds: " + std::to_string(arrays.size()) +
                                          " arrays given, " + std::to_string(i) + " expected");
            M.set_bonds(in, for_restore);
          },
          py::kw_only(), py::arg("for_restore") = false,
          "set_bonds(node, sigma_cr, tau_cr, G, pair_point, body_minus, body_plus, nx, ny, "
          "length, frame_p, frame_q, *, for_restore=False): the arrays of bond_input(), in its "
          "key order")
      .def("set_bond_params",
           [](Model& M, double mu, const std::string& direction, bool check_failure,
              int32_t screen_interval, double screen_fraction) {
             BondParams p;
             p.mu = mu;
             p.direction = cohesive_law::parse_direction(direction);
             p.check_failure = check_failure;
             p.screen_interval = screen_interval;
             p.screen_fraction = screen_fraction;
             M.set_bond_params(p);
           },
           py::arg("mu"), py::arg("direction"), py::arg("check_failure"),
           py::arg("screen_interval"), py::arg("screen_fraction"))
      .def("bond_params",
           [](const Model& M) {
             const BondParams& p = M.bonds().params();
             py::dict d;
             d["mu"] = std::isnan(p.mu) ? py::object(py::none()) : py::object(py::float_(p.mu));
             d["direction"] = cohesive_law::direction_name(p.direction);
             d["check_failure"] = p.check_failure;
             d["screen_interval"] = p.screen_interval;
             d["screen_fraction"] = p.screen_fraction;
             return d;
           })
      .def("bond_input", [](const Model& M) { return to_dict(M.bonds().input()); })
      // Arrays of codes: point_state PointState, pair_state PairState, mode FailureMode.
      .def("bond_state", [](const Model& M) { return to_dict(M.bonds().state()); })
      .def("restore_bond_state",
           [](Model& M, const py::dict& d) { M.restore_bonds(from_dict<BondState>(d, "bond state")); })
      .def("bond_parents", [](const Model& M) { return as_array(M.bonds().parents()); })
      .def("bond_tractions",
           [](const Model& M) { return py::make_tuple(as_array(M.bonds().last_tn()), as_array(M.bonds().last_tt())); })
      .def("bond_counts",
           [](const Model& M) {
             const FreezeBonds& B = M.bonds();
             py::dict d;
             d["points"] = B.n_points();
             d["pairs"] = B.n_pairs();
             d["split"] = B.n_split();
             d["failed"] = B.n_failed();
             d["late_detections"] = B.late_detections();
             d["checks"] = B.checks();
             return d;
           })
      .def("bond_energy", [](const Model& M) {
        const FreezeBonds& B = M.bonds();
        py::dict d;
        d["work"] = B.work();
        d["stored"] = B.stored();
        d["dissipated"] = B.work() - B.stored();
        d["dissipation_effective"] = B.dissipation_effective();
        return d;
      });
}

}  // namespace engine
