// Python access to the engine (wrapped by icerubble/engine/model.py, which is the
// documented API: validation messages, node sets, named results).
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include "bindings/bindings.hpp"
#include "model/model.hpp"
#include "engine_parameter_ranges.hpp"

#include <algorithm>
#include <cmath>

namespace py = pybind11;

namespace engine {

namespace {

using DArray = py::array_t<double, py::array::c_style | py::array::forcecast>;
using IArray = py::array_t<int32_t, py::array::c_style | py::array::forcecast>;

template <class T, class A>
std::vector<T> to_vector(const A& a) {
  return std::vector<T>(a.data(), a.data() + a.size());
}

// A read-only numpy view on an engine array; keeps the model alive. Valid
// until the array is reallocated (node splitting appends nodes). The state
// changes only through the model's methods (set_positions, ...), never by
// writing into a view.
template <class T>
py::array view(const std::vector<T>& v, py::object owner, ssize_t cols = 1) {
  const ssize_t rows = ssize_t(v.size()) / cols;
  py::array a = cols == 1
                    ? py::array_t<T>({rows}, {ssize_t(sizeof(T))}, v.data(), owner)
                    : py::array_t<T>({rows, cols}, {ssize_t(sizeof(T)) * cols, ssize_t(sizeof(T))}, v.data(), owner);
  a.attr("setflags")(py::arg("write") = false);
  return a;
}

py::array node_view(py::object self, const std::string& name) {
  const Nodes& N = self.cast<const Model&>().nodes();
  const std::vector<double>* arrays[] = {&N.x, &N.y, &N.x0, &N.y0, &N.vx, &N.vy, &N.mass, &N.mass_phys,
                                   &N.f_int_x, &N.f_int_y, &N.f_visc_x, &N.f_visc_y,
                                   &N.f_con_x, &N.f_con_y, &N.f_coh_x, &N.f_coh_y,
                                   &N.f_buoy_y, &N.drag_k, &N.f_x, &N.f_y, &N.r_x, &N.r_y};
  const char* names[] = {"x", "y", "x0", "y0", "vx", "vy", "mass", "mass_phys", "f_int_x", "f_int_y",
                         "f_visc_x", "f_visc_y", "f_con_x", "f_con_y", "f_coh_x", "f_coh_y",
                         "f_buoy_y", "drag_k", "f_x", "f_y", "r_x", "r_y"};
  for (size_t k = 0; k < sizeof(names) / sizeof(names[0]); ++k)
    if (name == names[k]) return view(*arrays[k], self);
  throw std::invalid_argument("unknown node array '" + name + "'");
}

py::array triangle_view(py::object self, const std::string& name) {
  const Triangles& T = self.cast<const Model&>().triangles();
  if (name == "triangles") return view(T.node, self, 3);
  if (name == "body") return view(T.body, self);
  if (name == "stress") return view(T.stress, self, 3);
  if (name == "area0") return view(T.area0, self);
  if (name == "f_corner" || name == "f_visc_corner") {
    // a copy, (fx, fy) of corners 0, 1, 2 per row, from the interleaved records
    const int off = name == "f_corner" ? CornerLoad::fx : CornerLoad::visc_x;
    py::array_t<double> out({ssize_t(T.size()), ssize_t(6)});
    double* o = out.mutable_data();
    for (size_t c = 0; c < 3 * size_t(T.size()); ++c) {
      o[2 * c] = T.corner_load[CornerLoad::stride * c + off];
      o[2 * c + 1] = T.corner_load[CornerLoad::stride * c + off + 1];
    }
    return out;
  }
  throw std::invalid_argument("unknown triangle array '" + name + "'");
}

py::dict energy_dict(const EnergyLedger& e) {
  py::dict d;
  d["kinetic"] = e.kinetic;
  d["elastic"] = e.elastic;
  d["contact"] = e.contact;
  d["friction"] = e.friction;
  d["damping"] = e.damping;
  d["drag"] = e.drag;
  d["cohesive"] = e.cohesive;
  d["cohesive_stored"] = e.cohesive_stored;
  d["work_gravity"] = e.work_gravity;
  d["work_buoyancy"] = e.work_buoyancy;
  d["work_boundary"] = e.work_boundary;
  d["initial"] = e.initial;
  d["elastic_midstep"] = e.elastic_midstep;
  d["contact_solver"] = e.contact_solver;
  d["friction_solver"] = e.friction_solver;
  // a ledger reset but not yet stepped (a checkpoint written as loading
  // starts) takes its initial energy at its first step, also when restored
  d["started"] = e.started ? 1.0 : 0.0;
  d["residual"] = e.residual();
  d["scale"] = e.scale();
  return d;
}

py::dict stable_dict(const StableStep& s, const Model& m) {
  py::dict d;
  d["dt"] = s.dt;
  d["safety"] = kTimeStepSafety;
  d["governing"] = s.governing();
  d["dt_element"] = s.dt_element;
  d["element"] = s.element;
  d["altitude"] = s.altitude;
  d["wave_speed"] = s.wave_speed;
  d["damping_ratio"] = s.damping_ratio;
  d["dt_contact"] = s.dt_contact;
  d["contact_node"] = s.contact_node;
  d["contact_mass"] = s.contact_mass;
  d["dt_drag"] = s.dt_drag;
  d["drag_body"] = s.drag_body;
  d["mass_scaling_dt"] = s.mass_scaling_dt;
  d["added_mass"] = s.added_mass;
  d["added_mass_fraction"] = s.added_mass_fraction;
  d["scaled_nodes"] = s.scaled_nodes;
  d["message"] = s.describe(m.triangles().body);
  return d;
}

// The engine's parameters across the binding: a dict with exactly these
// keys, the registry's names (icerubble/parameters.py, engine=True, less dt
// and dt_fraction, which set_dt and set_dt_fraction take).
const char* const kParameterNames[] = {
    "gravity", "g", "buoyancy", "drag", "rho_w", "y_w", "c_w", "drag_model", "C_d", "penalty", "mu",
    "check_stable_dt", "check_energy", "energy_tolerance", "local_damping", "mass_scaling_dt",
    "contact_reach", "threads", "sleeping", "sleep_velocity", "sleep_force", "sleep_quiet_steps"};

EngineParameters engine_parameters(const py::dict& d) {
  std::vector<std::string> unknown, missing;
  for (auto item : d) {
    const std::string k = py::str(item.first);
    if (std::find_if(std::begin(kParameterNames), std::end(kParameterNames),
                     [&](const char* n) { return k == n; }) == std::end(kParameterNames))
      unknown.push_back(k);
  }
  for (const char* n : kParameterNames)
    if (!d.contains(n)) missing.push_back(n);
  auto list = [](const std::vector<std::string>& v) {
    std::string s;
    for (const auto& x : v) s += (s.empty() ? "" : ", ") + x;
    return s;
  };
  if (!unknown.empty()) bad("set_parameters: unknown parameter(s) " + list(unknown));
  if (!missing.empty()) bad("set_parameters: missing parameter(s) " + list(missing));
  // types here (True is 1 to a double caster: `mu True` would run at 1); ranges in validate()
  auto boolean = [](py::handle v) {   // Python's bool or numpy's
    return py::isinstance<py::bool_>(v) || std::string(py::str(py::type::handle_of(v).attr("__name__"))) == "bool_";
  };
  const py::object real = py::module_::import("numbers").attr("Real");
  auto flag = [&](const char* k) {
    py::handle v = d[k];
    if (!boolean(v)) bad(std::string(k) + " must be True or False (got " + std::string(py::repr(v)) + ")");
    return v.cast<bool>();
  };
  auto number = [&](const char* k) {
    py::handle v = d[k];
    if (boolean(v) || !py::isinstance(v, real))
      bad("parameter " + std::string(k) + "=" + std::string(py::repr(v)) + " is not a number");
    return v.cast<double>();
  };
  // a count beyond the int the engine holds is refused by the registry's own range
  auto whole = [&](const char* k, const ParameterRange& range) {
    const double v = number(k);
    if (!(v == std::floor(v))) bad(std::string(k) + "=" + num(v) + " must be a whole number");
    if (!(v >= INT32_MIN && v <= INT32_MAX)) check(range, v);
    return int32_t(v);
  };
  EngineParameters p;
  p.external.gravity = flag("gravity");
  p.external.g = number("g");
  p.external.buoyancy = flag("buoyancy");
  p.external.drag = flag("drag");
  p.external.rho_w = number("rho_w");
  p.external.y_w = number("y_w");
  p.external.c_w = number("c_w");
  if (!py::isinstance<py::str>(d["drag_model"]))
    bad("parameter drag_model=" + std::string(py::repr(d["drag_model"])) + " is invalid: valid values are " +
        registry::drag_model_range);
  p.external.drag_model = drag_model_named(py::str(d["drag_model"]));
  p.external.C_d = number("C_d");
  p.contact.penalty = number("penalty");
  p.contact.mu = number("mu");
  p.check_stable_dt = flag("check_stable_dt");
  p.check_energy = flag("check_energy");
  p.energy_tolerance = number("energy_tolerance");
  p.local_damping = number("local_damping");
  p.mass_scaling_dt = number("mass_scaling_dt");
  p.contact_reach = number("contact_reach");
  p.threads = whole("threads", registry::threads);
  p.sleep.on = flag("sleeping");
  p.sleep.velocity = number("sleep_velocity");
  p.sleep.force = number("sleep_force");
  p.sleep.quiet_steps = whole("sleep_quiet_steps", registry::sleep_quiet_steps);
  return p;
}

py::dict parameters_dict(const EngineParameters& p) {
  py::dict d;
  d["gravity"] = p.external.gravity;
  d["g"] = p.external.g;
  d["buoyancy"] = p.external.buoyancy;
  d["drag"] = p.external.drag;
  d["rho_w"] = p.external.rho_w;
  d["y_w"] = p.external.y_w;
  d["c_w"] = p.external.c_w;
  d["drag_model"] = drag_model_name(p.external.drag_model);
  d["C_d"] = p.external.C_d;
  d["penalty"] = p.contact.penalty;
  d["mu"] = p.contact.mu;
  d["check_stable_dt"] = p.check_stable_dt;
  d["check_energy"] = p.check_energy;
  d["energy_tolerance"] = p.energy_tolerance;
  d["local_damping"] = p.local_damping;
  d["mass_scaling_dt"] = p.mass_scaling_dt;
  d["contact_reach"] = p.contact_reach;
  d["threads"] = p.threads;
  d["sleeping"] = p.sleep.on;
  d["sleep_velocity"] = p.sleep.velocity;
  d["sleep_force"] = p.sleep.force;
  d["sleep_quiet_steps"] = p.sleep.quiet_steps;
  return d;
}

}  // namespace

void bind_model(py::module_& m) {
  py::register_exception<InstabilityError>(m, "InstabilityError", PyExc_RuntimeError);
  m.def("engine_parameter_names", []() {
    py::list l;
    for (const char* n : kParameterNames) l.append(n);
    return l;
  }, "The keys of Model.set_parameters (the registry's names).");

  py::class_<Model>(m, "Model")
      .def(py::init([](DArray nodes, IArray tri, IArray body) {
             if (nodes.ndim() != 2 || nodes.shape(1) != 2)
               throw std::invalid_argument("nodes must be an (N, 2) array");
             if (tri.ndim() != 2 || tri.shape(1) != 3)
               throw std::invalid_argument("triangles must be an (M, 3) array");
             if (body.ndim() != 1) throw std::invalid_argument("body must be an (M,) array");
             return new Model(to_vector<double>(nodes), to_vector<int32_t>(tri), to_vector<int32_t>(body));
           }),
           py::arg("nodes"), py::arg("triangles"), py::arg("body"))
      .def("set_material",
           [](Model& M, int32_t b, double E, double nu, double rho, double damping, double viscosity) {
             Material mat;
             mat.E = E;
             mat.nu = nu;
             mat.rho = rho;
             mat.damping = damping;
             mat.viscosity = viscosity;
             M.set_material(b, mat);
           },
           py::arg("body"), py::arg("E"), py::arg("nu"), py::arg("rho"), py::arg("damping"),
           py::arg("viscosity") = 0.0)
      .def("set_dt", &Model::set_dt)
      .def("set_dt_fraction", &Model::set_dt_fraction, py::arg("fraction"),
           "dt = fraction x stable_step()['dt'] of the model as prepared now, fraction in (0, 1];\n"
           "fixed from then on (set_dt or set_dt_fraction again to change it).")
      .def("dt_control",
           [](const Model& M) {
             py::dict d;
             d["dt"] = M.dt();
             d["source"] = M.dt_fraction() > 0.0 ? "fraction" : M.dt() > 0.0 ? "explicit" : "unset";
             d["fraction"] = M.dt_fraction() > 0.0 ? py::object(py::float_(M.dt_fraction())) : py::object(py::none());
             return d;
           },
           "Which time step is in force: dt, source ('fraction', 'explicit' or 'unset'), fraction.")
      .def("set_parameters", [](Model& M, const py::dict& d) { M.set_parameters(engine_parameters(d)); },
           py::arg("parameters"),
           "Every engine parameter at once (a dict with exactly the keys of engine_parameter_names()),\n"
           "checked once against the ranges of icerubble/parameters.py (ValueError naming the first\n"
           "one out of range).")
      .def("parameters", [](const Model& M) { return parameters_dict(M.parameters()); })
      .def("thread_count", &Model::thread_count)
      .def("wake_all", &Model::wake_all)
      .def("asleep_nodes", &Model::asleep_nodes)
      .def("awake_triangles", &Model::awake_triangles)
      .def("sleep_state", [](const Model& M) {
        const SleepState s = M.sleep_state();
        py::dict d;
        d["sleep"] = as_array(s.sleep);
        d["quiet"] = as_array(s.quiet);
        d["f_ref_x"] = as_array(s.f_ref_x);
        d["f_ref_y"] = as_array(s.f_ref_y);
        d["window_start_step"] = s.window.start_step;
        d["window_start_time"] = s.window.start_time;
        for (const auto& [k, v] : {std::pair<const char*, const std::vector<double>*>{"window_cx", &s.window.cx},
                                   {"window_cy", &s.window.cy}, {"window_px", &s.window.px},
                                   {"window_py", &s.window.py}, {"window_l", &s.window.l}})
          d[k] = as_array(*v);
        return d;
      })
      .def("restore_sleep_state", [](Model& M, std::vector<uint8_t> sleep, std::vector<int32_t> quiet,
                                     std::vector<double> f_ref_x, std::vector<double> f_ref_y,
                                     int64_t window_start_step, double window_start_time, std::vector<double> cx,
                                     std::vector<double> cy, std::vector<double> px, std::vector<double> py,
                                     std::vector<double> l) {
        SleepWindow w;
        w.start_step = window_start_step;
        w.start_time = window_start_time;
        w.cx = std::move(cx);
        w.cy = std::move(cy);
        w.px = std::move(px);
        w.py = std::move(py);
        w.l = std::move(l);
        M.restore_sleep_state(SleepState{std::move(sleep), std::move(quiet), std::move(f_ref_x),
                                         std::move(f_ref_y), std::move(w)});
      }, py::arg("sleep"), py::arg("quiet"), py::arg("f_ref_x"), py::arg("f_ref_y"),
         py::arg("window_start_step"), py::arg("window_start_time"), py::arg("window_cx"),
         py::arg("window_cy"), py::arg("window_px"), py::arg("window_py"), py::arg("window_l"))
      .def("mass_floor", [](const Model& M) {
        return as_array(M.nodes().mass_floor);
      })
      .def("set_mass_floor", &Model::set_mass_floor, py::arg("floor"))
      .def("reach_origin", [](const Model& M) {
        return py::make_tuple(as_array(M.reach_origin_x()), as_array(M.reach_origin_y()));
      })
      .def("set_reach_origin", &Model::set_reach_origin, py::arg("x"), py::arg("y"))
      .def("raised_nodes", &Model::raised_nodes)
      .def("reset_contact_masses", &Model::reset_contact_masses,
           "Back from a larger mass-scaling step: floors dropped, masses of the current target, "
           "nodes raised where the present configuration needs it (returns how many)")
      .def("add_boundary_condition",
           [](Model& M, const std::string& name, IArray nodes, bool x, bool y, double dir_x,
              double dir_y, const std::string& kind, double value, double ramp_time, DArray t, DArray v) {
             BoundaryCondition bc;
             bc.name = name;
             bc.nodes = to_vector<int32_t>(nodes);
             bc.x = x;
             bc.y = y;
             bc.dir_x = dir_x;
             bc.dir_y = dir_y;
             if (kind == "constant") bc.history.kind = VelocityHistory::Kind::constant;
             else if (kind == "smooth_ramp") bc.history.kind = VelocityHistory::Kind::smooth_ramp;
             else if (kind == "table") bc.history.kind = VelocityHistory::Kind::table;
             else throw std::invalid_argument("kind must be 'constant', 'smooth_ramp' or 'table'");
             bc.history.value = value;
             bc.history.ramp_time = ramp_time;
             bc.history.t = to_vector<double>(t);
             bc.history.v = to_vector<double>(v);
             M.add_boundary_condition(bc);
           })
      .def("clear_boundary_conditions", &Model::clear_boundary_conditions)
      .def("velocity_history",
           [](const Model& M, const std::string& name, double t) {
             const int32_t k = M.find_boundary_condition(name);
             if (k < 0) throw std::invalid_argument("no boundary condition named '" + name + "'");
             return M.boundary_conditions()[k].history.at(t);
           })
      .def("reaction",
           [](const Model& M, IArray nodes) {
             double rx, ry;
             M.reaction(to_vector<int32_t>(nodes), rx, ry);
             return py::make_tuple(rx, ry);
           })
      .def("set_positions", [](Model& M, DArray x, DArray y) {
        M.set_positions(to_vector<double>(x), to_vector<double>(y));
      })
      .def("set_velocities", [](Model& M, DArray vx, DArray vy) {
        M.set_velocities(to_vector<double>(vx), to_vector<double>(vy));
      })
      .def("step", &Model::step, py::arg("n"), py::call_guard<py::gil_scoped_release>())
      .def("evaluate", &Model::evaluate, py::call_guard<py::gil_scoped_release>())
      .def("evaluate_before_cohesive", &Model::evaluate_before_cohesive, py::call_guard<py::gil_scoped_release>())
      .def("reset_energy", &Model::reset_energy)
      .def("restore_clock", &Model::restore_clock, py::arg("time"), py::arg("step_count"))
      .def("stable_step", [](Model& M) { return stable_dict(M.stable_step(), M); })
      .def("energy", [](const Model& M) { return energy_dict(M.energy()); })
      .def("contact_warm_start",
           [](const Model& M) {
             return py::make_tuple(M.contact().warm_start_keys(), M.contact().warm_start_forces());
           })
      .def("set_contact_warm_start",
           [](Model& M, const std::vector<uint64_t>& k, const std::vector<double>& f) {
             if (k.size() != f.size()) throw std::invalid_argument("warm start: keys and forces differ in length");
             M.set_contact_warm_start(k, f);
           })
      .def("restore_energy",
           [](Model& M, const py::dict& d) {
             EnergyLedger e;
             auto get = [&](const char* k) { return d[k].cast<double>(); };
             e.kinetic = get("kinetic");
             e.elastic = get("elastic");
             e.contact = get("contact");
             e.friction = get("friction");
             e.damping = get("damping");
             e.drag = get("drag");
             e.cohesive = get("cohesive");
             e.cohesive_stored = get("cohesive_stored");
             e.work_gravity = get("work_gravity");
             e.work_buoyancy = get("work_buoyancy");
             e.work_boundary = get("work_boundary");
             e.initial = get("initial");
             e.elastic_midstep = get("elastic_midstep");
             e.contact_solver = get("contact_solver");
             e.friction_solver = get("friction_solver");
             // checkpoints written before "started" was: always after a step
             e.started = !d.contains("started") || get("started") != 0.0;
             M.restore_energy(e);
           })
      .def("timings", [](const Model& M) {
        const StepTimings& t = M.timings();
        py::dict d;
        d["elements"] = t.elements;
        d["drag"] = t.drag;
        d["contact_detection"] = t.contact_detection;
        d["contact_forces"] = t.contact_forces;
        d["friction"] = t.friction;
        d["bonds"] = t.bonds;
        d["integration"] = t.integration;
        d["total"] = t.total;
        d["steps"] = t.steps;
        d["element_steps"] = t.element_steps;
        d["element_busy"] = t.element_busy;
        d["element_wait"] = t.element_wait;
        return d;
      })
      .def("node_array", &node_view)
      .def("triangle_array", &triangle_view)
      .def("surface_triangles", [](py::object self) {
        return view(const_cast<std::vector<int32_t>&>(self.cast<Model&>().surface_triangles()), self);
      })
      .def("surface_nodes", [](py::object self) {
        return view(const_cast<std::vector<uint8_t>&>(self.cast<Model&>().surface_nodes()), self);
      })
      .def("add_node", &Model::add_node)
      .def("set_triangle_node", &Model::set_triangle_node)
      .def_property_readonly("contact_list_builds", &Model::contact_list_builds)
      .def("rebuild_topology", &Model::rebuild_topology)
      .def("prepare", &Model::prepare_topology)
      .def_property_readonly("n_nodes", [](const Model& M) { return M.nodes().size(); })
      .def_property_readonly("n_triangles", [](const Model& M) { return M.triangles().size(); })
      .def_property_readonly("n_bodies", &Model::n_bodies)
      .def_property_readonly("time", &Model::time)
      .def_property_readonly("step_count", &Model::step_count)
      .def_property_readonly("dt", &Model::dt)
      .def_property_readonly("touching_pairs", &Model::touching_pairs)
      .def("memory_bytes", &Model::memory_bytes);
}

}  // namespace engine
