// Python access to the freeze bonds of a Model (wrapped by icerubble/fdem.py:
// Model.set_bond_points, Model.bonds, checkpoints). Adds methods to the Model
// class registered by model_bindings.cpp.
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <cmath>

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

template <class T>
py::array_t<T> arr(const std::vector<T>& v) {
  py::array_t<T> a(v.size());
  std::copy(v.begin(), v.end(), a.mutable_data());
  return a;
}

template <class T>
std::vector<T> item(const py::dict& d, const char* key) {
  if (!d.contains(key)) throw std::invalid_argument(std::string("bond state lacks '") + key + "'");
  return vec<T>(d[key]);
}

py::dict state_dict(const BondState& s) {
  py::dict d;
  d["time"] = s.time;
  d["step_count"] = s.step_count;
  d["point_state"] = arr(s.point_state);
  d["near"] = arr(s.near);
  d["t_split"] = arr(s.t_split);
  d["x_split"] = arr(s.x_split);
  d["y_split"] = arr(s.y_split);
  d["pair_state"] = arr(s.pair_state);
  d["node_plus"] = arr(s.node_plus);
  d["node_minus"] = arr(s.node_minus);
  d["fnx"] = arr(s.fnx);
  d["fny"] = arr(s.fny);
  d["f0"] = arr(s.f0);
  d["delta_f"] = arr(s.delta_f);
  d["delta_m"] = arr(s.delta_m);
  d["f_n_prev"] = arr(s.f_n_prev);
  d["f_t_prev"] = arr(s.f_t_prev);
  d["d_n_prev"] = arr(s.d_n_prev);
  d["d_t_prev"] = arr(s.d_t_prev);
  d["split_tn"] = arr(s.split_tn);
  d["split_tt"] = arr(s.split_tt);
  d["t_fail"] = arr(s.t_fail);
  d["x_fail"] = arr(s.x_fail);
  d["y_fail"] = arr(s.y_fail);
  d["dn_fail"] = arr(s.dn_fail);
  d["dt_fail"] = arr(s.dt_fail);
  d["mode"] = arr(s.mode);
  d["parent"] = arr(s.parent);
  d["work"] = s.work;
  d["dissipation_effective"] = s.dissipation_effective;
  d["stored"] = s.stored;
  d["late_detections"] = s.late_detections;
  d["checks"] = s.checks;
  return d;
}

BondState state_from(const py::dict& d) {
  BondState s;
  if (!d.contains("time") || !d.contains("step_count")) throw std::invalid_argument("bond state lacks the clock (time, step_count)");
  s.time = d["time"].cast<double>();
  s.step_count = d["step_count"].cast<int64_t>();
  s.point_state = item<int8_t>(d, "point_state");
  s.near = item<int8_t>(d, "near");
  s.t_split = item<double>(d, "t_split");
  s.x_split = item<double>(d, "x_split");
  s.y_split = item<double>(d, "y_split");
  s.pair_state = item<int8_t>(d, "pair_state");
  s.node_plus = item<int32_t>(d, "node_plus");
  s.node_minus = item<int32_t>(d, "node_minus");
  s.fnx = item<double>(d, "fnx");
  s.fny = item<double>(d, "fny");
  s.f0 = item<double>(d, "f0");
  s.delta_f = item<double>(d, "delta_f");
  s.delta_m = item<double>(d, "delta_m");
  s.f_n_prev = item<double>(d, "f_n_prev");
  s.f_t_prev = item<double>(d, "f_t_prev");
  s.d_n_prev = item<double>(d, "d_n_prev");
  s.d_t_prev = item<double>(d, "d_t_prev");
  s.split_tn = item<double>(d, "split_tn");
  s.split_tt = item<double>(d, "split_tt");
  s.t_fail = item<double>(d, "t_fail");
  s.x_fail = item<double>(d, "x_fail");
  s.y_fail = item<double>(d, "y_fail");
  s.dn_fail = item<double>(d, "dn_fail");
  s.dt_fail = item<double>(d, "dt_fail");
  s.mode = item<int8_t>(d, "mode");
  s.parent = item<int32_t>(d, "parent");
  s.work = d["work"].cast<double>();
  s.dissipation_effective = d["dissipation_effective"].cast<double>();
  s.stored = d["stored"].cast<double>();
  s.late_detections = d["late_detections"].cast<int64_t>();
  s.checks = d["checks"].cast<int64_t>();
  return s;
}

}  // namespace

void bind_freeze_bonds(py::module_& m) {
  (void)m;
  auto cls = py::reinterpret_borrow<py::class_<Model>>(py::type::of<Model>());
  cls.def("set_bonds",
          [](Model& M, py::handle node, py::handle sigma_cr, py::handle tau_cr, py::handle G,
             py::handle pair_point, py::handle body_minus, py::handle body_plus, py::handle nx,
             py::handle ny, py::handle length, py::handle frame_p, py::handle frame_q,
             bool for_restore) {
            BondInput in;
            in.node = vec<int32_t>(node);
            in.sigma_cr = vec<double>(sigma_cr);
            in.tau_cr = vec<double>(tau_cr);
            in.G = vec<double>(G);
            in.pair_point = vec<int32_t>(pair_point);
            in.body_minus = vec<int32_t>(body_minus);
            in.body_plus = vec<int32_t>(body_plus);
            in.nx = vec<double>(nx);
            in.ny = vec<double>(ny);
            in.length = vec<double>(length);
            in.frame_p = vec<int32_t>(frame_p);
            in.frame_q = vec<int32_t>(frame_q);
            M.bonds().set(M, in, for_restore);
          },
          py::arg("node"), py::arg("sigma_cr"), py::arg("tau_cr"), py::arg("G"),
          py::arg("pair_point"), py::arg("body_minus"), py::arg("body_plus"), py::arg("nx"),
          py::arg("ny"), py::arg("length"), py::arg("frame_p"), py::arg("frame_q"),
          py::arg("for_restore") = false)
      .def("set_bond_params",
           [](Model& M, double mu, const std::string& direction, bool check_failure,
              int32_t screen_interval, double screen_fraction) {
             BondParams p;
             p.mu = mu;
             p.direction = cohesive_law::parse_direction(direction);
             p.check_failure = check_failure;
             p.screen_interval = screen_interval;
             p.screen_fraction = screen_fraction;
             M.bonds().set_params(p);
           },
           py::arg("mu"), py::arg("direction"), py::arg("check_failure"),
           py::arg("screen_interval"), py::arg("screen_fraction"))
      .def("bond_params",
           [](Model& M) {
             const BondParams& p = M.bonds().params();
             py::dict d;
             d["mu"] = std::isnan(p.mu) ? py::object(py::none()) : py::object(py::float_(p.mu));
             d["direction"] = cohesive_law::direction_name(p.direction);
             d["check_failure"] = p.check_failure;
             d["screen_interval"] = p.screen_interval;
             d["screen_fraction"] = p.screen_fraction;
             return d;
           })
      .def("bond_input",
           [](Model& M) {
             const BondInput& in = M.bonds().input();
             py::dict d;
             d["node"] = arr(in.node);
             d["sigma_cr"] = arr(in.sigma_cr);
             d["tau_cr"] = arr(in.tau_cr);
             d["G"] = arr(in.G);
             d["pair_point"] = arr(in.pair_point);
             d["body_minus"] = arr(in.body_minus);
             d["body_plus"] = arr(in.body_plus);
             d["nx"] = arr(in.nx);
             d["ny"] = arr(in.ny);
             d["length"] = arr(in.length);
             d["frame_p"] = arr(in.frame_p);
             d["frame_q"] = arr(in.frame_q);
             return d;
           })
      .def("bond_state", [](Model& M) { return state_dict(M.bonds().state(M)); })
      .def("restore_bond_state",
           [](Model& M, const py::dict& d) { M.bonds().restore(M, state_from(d)); })
      .def("bond_parents", [](Model& M) { return arr(M.bonds().parents()); })
      .def("bond_tractions",
           [](Model& M) { return py::make_tuple(arr(M.bonds().last_tn()), arr(M.bonds().last_tt())); })
      .def("bond_counts",
           [](Model& M) {
             FreezeBonds& B = M.bonds();
             py::dict d;
             d["points"] = B.n_points();
             d["pairs"] = B.n_pairs();
             d["split"] = B.n_split();
             d["failed"] = B.n_failed();
             d["late_detections"] = B.late_detections();
             d["checks"] = B.checks();
             return d;
           })
      .def("bond_energy", [](Model& M) {
        FreezeBonds& B = M.bonds();
        py::dict d;
        d["work"] = B.work();
        d["stored"] = B.stored();
        d["dissipated"] = B.work() - B.stored();
        d["dissipation_effective"] = B.dissipation_effective();
        return d;
      });
}

}  // namespace engine
