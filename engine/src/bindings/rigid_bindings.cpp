// Python access to the rigid-block water law (rigid/rigid_water.hpp): arrays
// in, arrays out, for the discrete-only model's YADE scene.
#include <pybind11/numpy.h>

#include <algorithm>
#include <string>
#include <vector>

#include "bindings/bindings.hpp"
#include "common/input_errors.hpp"
#include "rigid/rigid_bonds.hpp"
#include "rigid/rigid_friction.hpp"
#include "rigid/rigid_water.hpp"

namespace py = pybind11;

namespace engine {

namespace {

using DArray = py::array_t<double, py::array::c_style | py::array::forcecast>;
using IArray = py::array_t<int32_t, py::array::c_style | py::array::forcecast>;

void require_length(const char* name, const DArray& a, ssize_t n) {
  if (a.ndim() != 1 || a.shape(0) != n)
    bad(std::string(name) + " must be a 1-D array of " + std::to_string(n) + " values (got " +
        std::to_string(a.size()) + ")");
  for (ssize_t i = 0; i < n; ++i)
    if (!std::isfinite(a.data()[i])) bad(std::string(name) + "[" + std::to_string(i) + "] is not finite");
}

void require_ids(const char* name, const IArray& a, ssize_t n, int32_t n_bodies) {
  if (a.ndim() != 1 || a.shape(0) != n)
    bad(std::string(name) + " must be a 1-D array of " + std::to_string(n) + " body ids");
  for (ssize_t i = 0; i < n; ++i)
    if (a.data()[i] < 0 || a.data()[i] >= n_bodies)
      bad(std::string(name) + "[" + std::to_string(i) + "] = " + std::to_string(a.data()[i]) +
          " is not a body id in [0, " + std::to_string(n_bodies - 1) + "]");
}

py::tuple friction_step(FrictionHistory& h, IArray a, IArray b, DArray px, DArray py_, DArray nx, DArray ny,
                        DArray fn, DArray x, DArray y, DArray vx, DArray vy, DArray omega, double dt,
                        double k_t, double mu) {
  const ssize_t nb = x.size(), nc = a.size();
  for (auto [name, arr] : {std::pair<const char*, DArray*>{"x", &x}, {"y", &y}, {"vx", &vx}, {"vy", &vy},
                           {"omega", &omega}})
    require_length(name, *arr, nb);
  require_ids("a", a, nc, int32_t(nb));
  require_ids("b", b, nc, int32_t(nb));
  for (auto [name, arr] : {std::pair<const char*, DArray*>{"px", &px}, {"py", &py_}, {"nx", &nx}, {"ny", &ny},
                           {"fn", &fn}})
    require_length(name, *arr, nc);
  for (ssize_t k = 0; k < nc; ++k) {
    if (!(a.data()[k] < b.data()[k]))
      bad("contact " + std::to_string(k) + ": a = " + std::to_string(a.data()[k]) + " must be < b = " +
          std::to_string(b.data()[k]) + " (the normal points from a to b)");
    const double len = std::hypot(nx.data()[k], ny.data()[k]);
    if (!(std::fabs(len - 1.0) < 1e-6))
      bad("contact " + std::to_string(k) + ": the normal must be a unit vector (length " + num(len) + ")");
    if (!(fn.data()[k] >= 0.0)) bad("contact " + std::to_string(k) + ": fn must be >= 0 N/m (got " + num(fn.data()[k]) + ")");
  }
  require_finite_positive("dt", dt, "s");
  require_finite_positive("k_t", k_t, "N/m per m width (tangential contact stiffness)");
  require_finite_nonnegative("mu", mu, "(friction coefficient)");
  RigidContacts c{int32_t(nc), a.data(), b.data(), px.data(), py_.data(), nx.data(), ny.data(), fn.data()};
  RigidBodies B{int32_t(nb), x.data(), y.data(), vx.data(), vy.data(), omega.data()};
  DArray ft(nc), fx(nb), fy(nb), tz(nb);
  rigid_friction(c, B, dt, k_t, mu, h, ft.mutable_data(), fx.mutable_data(), fy.mutable_data(), tz.mutable_data());
  return py::make_tuple(ft, fx, fy, tz);
}

}  // namespace

std::vector<double> column(const DArray& a2, int c, const char* name) {
  if (a2.ndim() != 2 || a2.shape(1) != 2) bad(std::string(name) + " must be an (n, 2) array");
  std::vector<double> out(size_t(a2.shape(0)));
  for (ssize_t i = 0; i < a2.shape(0); ++i) out[size_t(i)] = a2.data()[2 * i + c];
  return out;
}

std::vector<double> values(const DArray& a, size_t n, const char* name) {
  if (a.ndim() != 1 || size_t(a.shape(0)) != n)
    bad(std::string(name) + " must be a 1-D array of " + std::to_string(n) + " values (one per bond point)");
  return std::vector<double>(a.data(), a.data() + n);
}

// The bond points' floating-point history, by name (checkpoints).
std::vector<std::pair<const char*, std::vector<double>*>> history_doubles(RigidBondPoints& r) {
  return {{"f0", &r.f0}, {"delta_f", &r.delta_f}, {"delta_m", &r.delta_m}, {"dn_prev", &r.dn_prev},
          {"dt_prev", &r.dt_prev}, {"dissipated", &r.dissipated}, {"t_initiated", &r.t_initiated},
          {"t_failed", &r.t_failed}, {"f_n", &r.f_n}, {"f_t", &r.f_t}};
}

void bind_rigid(py::module_& m) {
  py::class_<RigidBondPoints>(m, "RigidBonds",
                              "Freeze bonds between rigid blocks: initially elastic, then the paper's "
                              "softening (rigid/rigid_bonds.hpp)")
      .def(py::init([](IArray a, IArray b, DArray anchor_a, DArray anchor_b, DArray normal_a, DArray k, DArray l,
                       DArray sigma_cr, DArray tau_cr, DArray mu, DArray G, int n_bodies, std::string direction) {
             RigidBondPoints r;
             if (a.ndim() != 1 || b.ndim() != 1 || a.size() != b.size()) bad("a and b must be 1-D arrays of the same length");
             const size_t n = size_t(a.size());
             r.a.assign(a.data(), a.data() + n);
             r.b.assign(b.data(), b.data() + n);
             r.ax = column(anchor_a, 0, "anchor_a");
             r.ay = column(anchor_a, 1, "anchor_a");
             r.bx = column(anchor_b, 0, "anchor_b");
             r.by = column(anchor_b, 1, "anchor_b");
             r.nx = column(normal_a, 0, "normal_a");
             r.ny = column(normal_a, 1, "normal_a");
             r.k = values(k, n, "k");
             r.l = values(l, n, "l");
             r.sigma_cr = values(sigma_cr, n, "sigma_cr");
             r.tau_cr = values(tau_cr, n, "tau_cr");
             r.mu = values(mu, n, "mu");
             r.G = values(G, n, "G");
             if (direction == "paper") r.direction = cohesive_law::ForceDirection::paper;
             else if (direction == "work_conjugate") r.direction = cohesive_law::ForceDirection::work_conjugate;
             else bad("direction must be 'paper' or 'work_conjugate' (got '" + direction + "')");
             if (n_bodies < 0) bad("n_bodies must be >= 0");
             r.validate_and_reset(n_bodies);
             return r;
           }),
           py::arg("a"), py::arg("b"), py::arg("anchor_a"), py::arg("anchor_b"), py::arg("normal_a"), py::arg("k"),
           py::arg("l"), py::arg("sigma_cr"), py::arg("tau_cr"), py::arg("mu"), py::arg("G"), py::arg("n_bodies"),
           py::arg("direction") = "paper")
      .def("step", [](RigidBondPoints& r, DArray x, DArray y, DArray theta, double time) {
             const ssize_t nb = x.size();
             require_length("x", x, nb);
             require_length("y", y, nb);
             require_length("theta", theta, nb);
             for (int32_t i = 0; i < r.size(); ++i)
               if (r.a[i] >= nb || r.b[i] >= nb) bad("x, y, theta must cover every body of the bond points");
             DArray fx(nb), fy(nb), tz(nb);
             r.step(int32_t(nb), x.data(), y.data(), theta.data(), time, fx.mutable_data(), fy.mutable_data(),
                    tz.mutable_data());
             return py::make_tuple(fx, fy, tz);
           }, py::arg("x"), py::arg("y"), py::arg("theta"), py::arg("time"),
           "One step to the body poses: (fx, fy, tz) per body [N/m, N/m, N m/m].")
      .def_property_readonly("state", [](const RigidBondPoints& r) { return as_array(r.state); })
      .def_property_readonly("mode", [](const RigidBondPoints& r) { return as_array(r.mode); })
      .def_property_readonly("f_n", [](const RigidBondPoints& r) { return as_array(r.f_n); })
      .def_property_readonly("f_t", [](const RigidBondPoints& r) { return as_array(r.f_t); })
      .def_property_readonly("dissipated", [](const RigidBondPoints& r) { return as_array(r.dissipated); })
      .def_property_readonly("t_initiated", [](const RigidBondPoints& r) { return as_array(r.t_initiated); })
      .def_property_readonly("t_failed", [](const RigidBondPoints& r) { return as_array(r.t_failed); })
      .def_readwrite("failure", &RigidBondPoints::failure,
                     "False: intact points stay intact whatever their traction (settling)")
      .def("stored_energy", &RigidBondPoints::stored_energy)
      .def("history", [](const RigidBondPoints& r) {
             py::dict h;
             h["state"] = as_array(r.state);
             h["mode"] = as_array(r.mode);
             for (auto [name, v] : history_doubles(const_cast<RigidBondPoints&>(r))) h[name] = as_array(*v);
             h["failure"] = r.failure;
             h["failure_last_step"] = r.failure_last_step;
             return h;
           }, "Every bond point's history, for a checkpoint (restore_history continues it).")
      .def("restore_history", [](RigidBondPoints& r, py::dict h) {
             const size_t n = r.a.size();
             auto int8s = [&](const char* name, std::vector<int8_t>& out) {
               auto a = h[name].cast<py::array_t<int8_t, py::array::c_style | py::array::forcecast>>();
               if (a.ndim() != 1 || size_t(a.shape(0)) != n)
                 bad(std::string("history ") + name + " must have one value per bond point (" + std::to_string(n) + ")");
               out.assign(a.data(), a.data() + n);
             };
             int8s("state", r.state);
             int8s("mode", r.mode);
             for (auto [name, v] : history_doubles(r)) *v = values(h[name].cast<DArray>(), n, name);
             r.failure = h["failure"].cast<bool>();
             r.failure_last_step = h["failure_last_step"].cast<bool>();
           }, py::arg("history"), "Continue a checkpointed history (from history()).");
  py::class_<FrictionHistory>(m, "RigidFriction",
                              "Coulomb friction with stick between rigid blocks, one history per body pair "
                              "(rigid/rigid_friction.hpp)")
      .def(py::init<>())
      .def("step", &friction_step, py::arg("a"), py::arg("b"), py::arg("px"), py::arg("py"), py::arg("nx"),
           py::arg("ny"), py::arg("fn"), py::arg("x"), py::arg("y"), py::arg("vx"), py::arg("vy"),
           py::arg("omega"), py::arg("dt"), py::arg("k_t"), py::arg("mu"),
           "One step: (ft per contact [N/m], fx, fy, tz per body [N/m, N m/m]); the history moves on.")
      .def("stick", [](FrictionHistory& h, IArray a, IArray b) {
        if (a.ndim() != 1 || b.ndim() != 1 || a.size() != b.size())
          bad("a and b must be 1-D arrays of the same length (one body pair each)");
        for (ssize_t k = 0; k < a.size(); ++k) {
          if (!(a.data()[k] >= 0 && a.data()[k] < b.data()[k]))
            bad("pair " + std::to_string(k) + ": (" + std::to_string(a.data()[k]) + ", " +
                std::to_string(b.data()[k]) + ") must be body ids with 0 <= a < b");
          h.stuck.push_back(friction_key(a.data()[k], b.data()[k]));
        }
        std::sort(h.stuck.begin(), h.stuck.end());
        h.stuck.erase(std::unique(h.stuck.begin(), h.stuck.end()), h.stuck.end());
      }, py::arg("a"), py::arg("b"),
           "Make body pairs (a < b) stick at any tangential force from now on (no Coulomb cap).")
      .def_property_readonly("stuck", [](const FrictionHistory& h) {
        return as_array(h.stuck);
      }, "The keys (a << 32 | b) of the pairs that stick, ascending.")
      .def_property_readonly("keys", [](const FrictionHistory& h) {
        return as_array(h.key);
      })
      .def_property_readonly("forces", [](const FrictionHistory& h) {
        return as_array(h.ft);
      })
      .def("restore", [](FrictionHistory& h, py::array_t<uint64_t, py::array::c_style | py::array::forcecast> keys,
                         DArray forces) {
        if (keys.size() != forces.size()) bad("keys and forces must have the same length");
        for (ssize_t i = 1; i < keys.size(); ++i)
          if (!(keys.data()[i - 1] < keys.data()[i])) bad("friction history keys must ascend strictly");
        require_length("forces", forces, keys.size());
        h.key.assign(keys.data(), keys.data() + keys.size());
        h.ft.assign(forces.data(), forces.data() + forces.size());
      }, py::arg("keys"), py::arg("forces"), "Continue a checkpointed history.");
  m.def(
      "rigid_water_forces",
      [](IArray offset, DArray vx, DArray vy, DArray area, DArray cx, DArray cy, DArray theta, DArray ux,
         DArray uy, DArray omega, double y_w, double rho_w, double g, bool buoyancy, const std::string& drag_model,
         double c_w, double C_d, int threads) {
        const ssize_t n = offset.size() - 1;
        if (offset.ndim() != 1 || n < 0) bad("offset must be a 1-D array of n_blocks + 1 corner offsets");
        const int32_t* o = offset.data();
        if (o[0] != 0) bad("offset[0] must be 0");
        for (ssize_t k = 0; k < n; ++k)
          if (o[k + 1] - o[k] < 3)
            bad("block " + std::to_string(k) + " has " + std::to_string(o[k + 1] - o[k]) +
                " corners: a block needs >= 3 (offset must increase by >= 3)");
        require_length("vx (body-frame corners)", vx, o[n]);
        require_length("vy (body-frame corners)", vy, o[n]);
        for (auto [name, a] : {std::pair<const char*, DArray*>{"area", &area}, {"cx", &cx}, {"cy", &cy},
                               {"theta", &theta}, {"ux", &ux}, {"uy", &uy}, {"omega", &omega}})
          require_length(name, *a, n);
        for (ssize_t k = 0; k < n; ++k)
          if (!(area.data()[k] > 0.0))
            bad("area[" + std::to_string(k) + "] must be > 0 m² (got " + num(area.data()[k]) + ")");
        if (threads < 1) bad("threads must be >= 1 (got " + std::to_string(threads) + ")");
        ExternalParams p;
        p.y_w = y_w;
        p.rho_w = rho_w;
        p.g = g;
        p.buoyancy = buoyancy;
        p.drag_model = drag_model_named(drag_model);
        p.drag = p.drag_model != DragModel::None;
        p.c_w = c_w;
        p.C_d = C_d;
        validate(p);  // against the registry's ranges
        RigidBlocks b{int32_t(n), o, vx.data(), vy.data(), area.data(), cx.data(), cy.data(),
                      theta.data(), ux.data(), uy.data(), omega.data()};
        DArray fx(n), fy(n), tz(n);
        {
          py::gil_scoped_release nogil;
          rigid_water_forces(b, p, fx.mutable_data(), fy.mutable_data(), tz.mutable_data(), threads);
        }
        return py::make_tuple(fx, fy, tz);
      },
      py::arg("offset"), py::arg("vx"), py::arg("vy"), py::arg("area"), py::arg("cx"), py::arg("cy"),
      py::arg("theta"), py::arg("ux"), py::arg("uy"), py::arg("omega"), py::arg("y_w"), py::arg("rho_w"),
      py::arg("g"), py::arg("buoyancy"), py::arg("drag_model"), py::arg("c_w"), py::arg("C_d"),
      py::arg("threads") = 1,
      "Buoyancy and drag on rigid polygon blocks per metre of width: (fx, fy, tz) [N/m, N m/m].\n"
      "Corners (vx, vy) are body-frame, relative to each block's centroid; drag_model 'none',\n"
      "'linear' (c_w) or 'quadratic' (C_d). docs/model.md §6.");
}

}  // namespace engine
