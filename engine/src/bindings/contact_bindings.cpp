// Python access to the contact module alone (pair kernel tests, diagnostics):
//   contact_pair(...)      the force between two triangles;
//   ContactSolver          the two contact passes on flat node/element arrays;
//   candidate_layout(...)  a candidate list as the GPU's contact stages read it.
#include <optional>
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <stdexcept>
#include <string>

#include "bindings/bindings.hpp"
#include "contact/candidate_layout.hpp"
#include "contact/contact.hpp"

namespace py = pybind11;

namespace engine {
namespace {

using DArr = py::array_t<double, py::array::c_style | py::array::forcecast>;
using IArr = py::array_t<int32_t, py::array::c_style | py::array::forcecast>;

// Keeps the converted arrays alive while `in` points into them.
struct InputHolder {
  DArr x, y, vx, vy, mass;
  IArr tri, body, surface;
  ContactInput in;
  py::array_t<uint8_t, py::array::c_style | py::array::forcecast> constrained;
  DArr vbx, vby;
};

void need_len(const char* name, py::ssize_t got, py::ssize_t want) {
  if (got != want)
    throw std::invalid_argument(std::string(name) + " must have length " + std::to_string(want) +
                                ", got " + std::to_string(got));
}

// Optional prescribed-velocity components (bit 0: x, bit 1: y) and, optionally,
// their prescribed velocities.
void add_constraints(InputHolder& h, py::object constrained, py::object vbx, py::object vby) {
  if (constrained.is_none()) return;
  h.constrained = constrained.cast<py::array_t<uint8_t, py::array::c_style | py::array::forcecast>>();
  need_len("constrained", h.constrained.size(), h.in.n_nodes);
  h.in.constrained = h.constrained.data();
  if (vbx.is_none() != vby.is_none())
    throw std::invalid_argument("give both v_bc_x and v_bc_y, or neither");
  if (vbx.is_none()) return;
  h.vbx = vbx.cast<DArr>();
  h.vby = vby.cast<DArr>();
  need_len("v_bc_x", h.vbx.size(), h.in.n_nodes);
  need_len("v_bc_y", h.vby.size(), h.in.n_nodes);
  h.in.v_bc_x = h.vbx.data();
  h.in.v_bc_y = h.vby.data();
}

InputHolder make_input(DArr x, DArr y, DArr vx, DArr vy, DArr mass, IArr tri, IArr body,
                       IArr surface, double dt) {
  InputHolder h{x, y, vx, vy, mass, tri, body, surface, {}, {}, {}, {}};
  const py::ssize_t n = x.size();
  need_len("y", y.size(), n);
  need_len("vx", vx.size(), n);
  need_len("vy", vy.size(), n);
  need_len("mass", mass.size(), n);
  if (tri.size() % 3 != 0) throw std::invalid_argument("tri must hold 3 node ids per triangle");
  const py::ssize_t nt = tri.size() / 3;
  need_len("body", body.size(), nt);
  const int32_t* t = tri.data();
  for (py::ssize_t i = 0; i < 3 * nt; ++i)
    if (t[i] < 0 || t[i] >= n)
      throw std::invalid_argument("tri node ids must be in [0, n_nodes)");
  const int32_t* s = surface.data();
  for (py::ssize_t i = 0; i < surface.size(); ++i)
    if (s[i] < 0 || s[i] >= nt)
      throw std::invalid_argument("surface_tris ids must be in [0, n_tri)");
  h.in.n_nodes = static_cast<int32_t>(n);
  h.in.x = h.x.data();
  h.in.y = h.y.data();
  h.in.vx = h.vx.data();
  h.in.vy = h.vy.data();
  h.in.mass = h.mass.data();
  h.in.n_tri = static_cast<int32_t>(nt);
  h.in.tri = t;
  h.in.body = h.body.data();
  h.in.n_surface = static_cast<int32_t>(surface.size());
  h.in.surface_tris = s;
  h.in.dt = dt;
  return h;
}

// fx, fy are updated in place: refuse anything that would need a converted copy.
double* writable(py::array& a, const char* name, py::ssize_t n) {
  if (!a.dtype().is(py::dtype::of<double>()) || !(a.flags() & py::array::c_style) ||
      !a.writeable())
    throw std::invalid_argument(std::string(name) + " must be a writable contiguous float64 array");
  need_len(name, a.size(), n);
  return static_cast<double*>(a.mutable_data());
}

py::dict pair_dict(const PairContact& r) {
  py::dict d;
  py::array_t<double> f({6, 2});
  auto fm = f.mutable_unchecked<2>();
  for (int k = 0; k < 6; ++k) {
    fm(k, 0) = r.fx[k];
    fm(k, 1) = r.fy[k];
  }
  d["forces"] = f;
  d["energy"] = r.energy;
  d["area"] = r.area;
  d["point"] = py::make_tuple(r.px, r.py);
  d["nc"] = py::make_tuple(r.nc[0], r.nc[1], r.nc[2]);
  d["nt"] = py::make_tuple(r.nt[0], r.nt[1], r.nt[2]);
  return d;
}

}  // namespace

void bind_contact(py::module_& m) {
  m.def(
      "contact_pair",
      [](DArr xc, DArr xt, double penalty) -> py::object {
        if (xc.size() != 6 || xt.size() != 6)
          throw std::invalid_argument("xc and xt must be 3x2 arrays of vertex coordinates");
        if (!(std::isfinite(penalty) && penalty > 0.0))
          throw std::invalid_argument("penalty must be finite and > 0");
        const double* c = xc.data();
        const double* t = xt.data();
        const double xa[3] = {c[0], c[2], c[4]}, ya[3] = {c[1], c[3], c[5]};
        const double xb[3] = {t[0], t[2], t[4]}, yb[3] = {t[1], t[3], t[5]};
        PairContact r;
        if (!potential_contact_pair(xa, ya, xb, yb, penalty, r)) return py::none();
        return pair_dict(r);
      },
      py::arg("xc"), py::arg("xt"), py::arg("penalty"),
      "Potential contact between a contactor and a target triangle (eqs 1-3).\n"
      "xc, xt: 3x2 vertex coordinates. Returns None without overlap, else a dict:\n"
      "forces (6x2: contactor nodes then target nodes), energy = s int (phi_c+phi_t),\n"
      "area and point (centroid) of the overlap, nc/nt shape functions there.");

  m.def(
      "candidate_layout",
      [](IArr candidates, IArr tri, int32_t n_nodes) {
        if (candidates.ndim() != 2 || candidates.shape(1) != 2)
          throw std::invalid_argument("candidates must be an (n, 2) array of triangle ids (contactor, target)");
        if (tri.ndim() != 2 || tri.shape(1) != 3) throw std::invalid_argument("tri must be an (m, 3) array of node ids");
        if (n_nodes < 0) throw std::invalid_argument("n_nodes must be >= 0");
        const int32_t* t = tri.data();
        for (py::ssize_t k = 0; k < tri.size(); ++k)
          if (t[k] < 0 || t[k] >= n_nodes)
            throw std::invalid_argument("tri holds node " + std::to_string(t[k]) + ", outside 0.." +
                                        std::to_string(n_nodes - 1));
        std::vector<CandidatePair> cand(size_t(candidates.shape(0)));
        const int32_t* c = candidates.data();
        for (size_t k = 0; k < cand.size(); ++k) {
          cand[k] = {c[2 * k], c[2 * k + 1]};
          for (const int32_t v : {cand[k].a, cand[k].b})
            if (v < 0 || v >= tri.shape(0))
              throw std::invalid_argument("candidates hold triangle " + std::to_string(v) + ", outside 0.." +
                                          std::to_string(tri.shape(0) - 1));
        }
        CandidateLayout L;
        lay_out_candidates(cand, t, n_nodes, L);
        py::dict d;
        d["contactor"] = as_array(L.contactor);
        d["target"] = as_array(L.target);
        d["node"] = as_array(L.node);
        d["key"] = as_array(L.key);
        d["start"] = as_array(L.start);
        d["entry"] = as_array(L.entry);
        return d;
      },
      py::arg("candidates"), py::arg("tri"), py::arg("n_nodes"),
      "A candidate list as the GPU's contact stages read it (contact/candidate_layout.hpp): the\n"
      "candidates in the CPU's pair order ('contactor', 'target'), six nodes each ('node'), their\n"
      "friction keys ('key'), and node i's entries 6 c + k in candidate order\n"
      "('entry'[start[i]:start[i + 1]]).");

  m.def(
      "friction_islands",
      [](IArr node, int32_t n_nodes, int threads) {
        if (threads < 1) throw std::invalid_argument("threads must be >= 1");
        if (node.ndim() != 2 || node.shape(1) != 6) throw std::invalid_argument("node must be (pairs, 6)");
        if (!(n_nodes > 0)) throw std::invalid_argument("n_nodes must be > 0");
        const int32_t* v = node.data();
        for (py::ssize_t e = 0; e < node.size(); ++e)
          if (v[e] < 0 || v[e] >= n_nodes)
            throw std::invalid_argument("node ids must be in [0, n_nodes = " + std::to_string(n_nodes) + ")");
        FrictionIslands out;
        std::vector<int32_t> owner;
        {
          py::gil_scoped_release nogil;
          friction_islands(int32_t(node.shape(0)), v, n_nodes, out, owner, threads);
        }
        py::dict d;
        d["of_pair"] = as_array(out.of_pair);
        d["by_size"] = as_array(out.by_size);
        return d;
      },
      py::arg("node"), py::arg("n_nodes"), py::arg("threads") = 1,
      "The islands of pairs given by their six nodes each (contact/friction_islands.hpp), found on\n"
      "`threads` threads: 'of_pair',\n"
      "each pair's island (numbered by their first pair), and 'by_size', the islands largest first.");

  m.def(
      "contact_critical_dt",
      [](DArr x, DArr y, DArr mass, IArr tri, double penalty, std::optional<IArr> body_in, double reach) {
        if (!(reach > 0.0)) throw std::invalid_argument("reach must be > 0 m (inf: the whole mesh)");
        const py::ssize_t n = x.size();
        DArr zero(n);
        std::fill(zero.mutable_data(), zero.mutable_data() + n, 0.0);
        IArr body(tri.size() / 3), surface(0);
        if (body_in) {
          if (body_in->size() != body.size())
            throw std::invalid_argument("body must have one entry per triangle");
          std::copy(body_in->data(), body_in->data() + body.size(), body.mutable_data());
        } else {
          std::fill(body.mutable_data(), body.mutable_data() + body.size(), 0);
        }
        InputHolder h = make_input(x, y, zero, zero, mass, tri, body, surface, 0.0);
        const ContactStableStep s = contact_critical_dt(validated_contact_params(penalty, 0.0), h.in, nullptr, reach);
        py::dict d;
        d["dt"] = s.dt;
        d["node"] = s.node;
        d["stiffness"] = s.stiffness;
        d["mass"] = s.mass;
        return d;
      },
      py::arg("x"), py::arg("y"), py::arg("mass"), py::arg("tri"), py::arg("penalty"),
      py::arg("body") = py::none(), py::arg("reach") = INFINITY,
      "Critical time step of the contact penalty (no safety factor), see contact.hpp.\n"
      "body: body id per triangle (default: one body; disjoint meshes still have boundaries).\n"
      "reach: count only other bodies' boundaries within this distance of each edge [m].");

  py::class_<ContactSolver>(m, "ContactSolver",
                            "Broad phase, potential contact and Coulomb friction on flat arrays.")
      .def(py::init([](double skin_fraction) {
             auto s = std::make_unique<ContactSolver>();
             s->set_skin_fraction(skin_fraction);
             return s;
           }),
           py::arg("skin_fraction") = 0.1,
           "skin_fraction: candidate-list reuse margin (fraction of the largest surface\n"
           "triangle); 0 rebuilds the broad phase on every call.")
      .def_property_readonly("rebuilds", &ContactSolver::rebuilds)
      .def(
          "compute_normal",
          [](ContactSolver& s, DArr x, DArr y, DArr vx, DArr vy, DArr mass, IArr tri, IArr body,
             IArr surface, py::array fx, py::array fy, double penalty,
             double mu, double dt) {
            InputHolder h = make_input(x, y, vx, vy, mass, tri, body, surface, dt);
            double* px = writable(fx, "fx", h.in.n_nodes);
            double* py_ = writable(fy, "fy", h.in.n_nodes);
            const ContactParams p = validated_contact_params(penalty, mu);
            py::gil_scoped_release nogil;
            return s.compute_normal(p, h.in, px, py_);
          },
          py::arg("x"), py::arg("y"), py::arg("vx"), py::arg("vy"), py::arg("mass"),
          py::arg("tri"), py::arg("body"), py::arg("surface_tris"), py::arg("fx"), py::arg("fy"),
          py::arg("penalty"), py::arg("mu"), py::arg("dt"),
          "Adds normal contact forces to fx, fy in place; returns the touching pair count.")
      .def(
          "apply_friction",
          [](ContactSolver& s, DArr x, DArr y, DArr vx, DArr vy, DArr mass, IArr tri, IArr body,
             IArr surface, py::array fx, py::array fy, double penalty,
             double mu, double dt, py::object constrained, py::object vbx, py::object vby) {
            InputHolder h = make_input(x, y, vx, vy, mass, tri, body, surface, dt);
            add_constraints(h, constrained, vbx, vby);
            double* px = writable(fx, "fx", h.in.n_nodes);
            double* py_ = writable(fy, "fy", h.in.n_nodes);
            const ContactParams p = validated_contact_params(penalty, mu);
            py::gil_scoped_release nogil;
            return s.apply_friction(p, h.in, px, py_);
          },
          py::arg("x"), py::arg("y"), py::arg("vx"), py::arg("vy"), py::arg("mass"),
          py::arg("tri"), py::arg("body"), py::arg("surface_tris"), py::arg("fx"), py::arg("fy"),
          py::arg("penalty"), py::arg("mu"), py::arg("dt"), py::arg("constrained") = py::none(),
          py::arg("v_bc_x") = py::none(), py::arg("v_bc_y") = py::none(),
          "Adds friction forces to fx, fy (which must hold every other force of the step);\n"
          "returns the friction dissipation rate [W per m width].")
      .def_property_readonly("stored_energy", &ContactSolver::stored_energy)
      .def_property_readonly("touching_pairs", &ContactSolver::touching_pairs)
      .def_property_readonly("candidates",
                             [](const ContactSolver& s) {
                               const auto& c = s.candidates();
                               py::array_t<int32_t> a({static_cast<py::ssize_t>(c.size()),
                                                       static_cast<py::ssize_t>(2)});
                               auto am = a.mutable_unchecked<2>();
                               for (size_t i = 0; i < c.size(); ++i) {
                                 am(i, 0) = c[i].a;
                                 am(i, 1) = c[i].b;
                               }
                               return a;
                             })
      .def_property_readonly("sweep_order",
                             [](const ContactSolver& s) {
                               const FrictionOrder& o = s.sweep_order();
                               py::dict d;
                               d["pair"] = as_array(o.pair);
                               d["colour_start"] = as_array(o.colour_start);
                               return d;
                             },
                             "The last friction call's sweep order: 'pair' (pair indices, colour by\n"
                             "colour) and 'colour_start' (colour c is pair[colour_start[c]:colour_start[c+1]]).")
      .def_property_readonly("friction_forces",
                             [](const ContactSolver& s) {
                               const std::vector<double> f = s.friction_forces();
                               return as_array(f);
                             },
                             "The last friction call's tangential force per pair [N/m], pair order.")
      .def_property_readonly("pairs",
                             [](const ContactSolver& s) {
                               const auto& ps = s.pairs();
                               const py::ssize_t n = static_cast<py::ssize_t>(ps.size());
                               py::array_t<int32_t> tris({n, static_cast<py::ssize_t>(2)});
                               py::array_t<double> point({n, static_cast<py::ssize_t>(2)});
                               py::array_t<double> normal({n, static_cast<py::ssize_t>(2)});
                               py::array_t<double> fn(n), en(n);
                               auto t = tris.mutable_unchecked<2>();
                               auto pt = point.mutable_unchecked<2>();
                               auto nm = normal.mutable_unchecked<2>();
                               auto f = fn.mutable_unchecked<1>();
                               auto e = en.mutable_unchecked<1>();
                               for (py::ssize_t i = 0; i < n; ++i) {
                                 t(i, 0) = ps[i].contactor;
                                 t(i, 1) = ps[i].target;
                                 pt(i, 0) = ps[i].px;
                                 pt(i, 1) = ps[i].py;
                                 nm(i, 0) = ps[i].nx;
                                 nm(i, 1) = ps[i].ny;
                                 f(i) = ps[i].fn;
                                 e(i) = ps[i].energy;
                               }
                               py::dict d;
                               d["tris"] = tris;
                               d["point"] = point;
                               d["normal"] = normal;
                               d["fn"] = fn;
                               d["energy"] = en;
                               return d;
                             })
      .def_property_readonly("timings", [](const ContactSolver& s) {
        py::dict d;
        d["detection_s"] = s.timings().detection_s;
        d["forces_s"] = s.timings().forces_s;
        return d;
      });
}

}  // namespace engine
