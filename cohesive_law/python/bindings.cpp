// Python binding of the freeze-bond law: module icerubble._cohesive_law.
// Every function takes array-likes that broadcast against each other (numpy rules) and
// returns arrays of the broadcast shape; parameters are validated element by element
// before any result is computed (ValueError naming the parameter).
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cstdint>
#include <string>
#include <vector>

#include "cohesive_law/freeze_bond.hpp"

namespace py = pybind11;
namespace cl = cohesive_law;

namespace {

using Arr = py::array_t<double, py::array::c_style | py::array::forcecast>;

// numpy-broadcast the inputs and return contiguous float64 copies plus the common shape.
struct Broadcast {
  std::vector<Arr> in;
  std::vector<py::ssize_t> shape;
  py::ssize_t size = 0;
  explicit Broadcast(const std::vector<py::object>& args) {
    py::module_ np = py::module_::import("numpy");
    py::tuple b = np.attr("broadcast_arrays")(*py::tuple(py::cast(args)));
    for (auto a : b) in.push_back(Arr(np.attr("ascontiguousarray")(a, "float64")));
    const Arr& a0 = in.front();
    shape.assign(a0.shape(), a0.shape() + a0.ndim());
    size = a0.size();
  }
  const double* operator[](std::size_t i) const { return in[i].data(); }
  Arr out() const { return Arr(shape); }
  py::array_t<std::int8_t> out_i8() const { return py::array_t<std::int8_t>(shape); }
  py::array_t<bool> out_bool() const { return py::array_t<bool>(shape); }
};

void each_positive(const char* name, const double* v, py::ssize_t n) {
  for (py::ssize_t i = 0; i < n; ++i) cl::require_positive(name, v[i]);
}
void each_finite(const char* name, const double* v, py::ssize_t n) {
  for (py::ssize_t i = 0; i < n; ++i) cl::require_finite(name, v[i]);
}

// Tractions and strengths of eqs 5-6, broadcast together and validated.
Broadcast traction_args(py::object t_n, py::object t_t, py::object sigma_cr, py::object tau_cr,
                        py::object mu) {
  Broadcast b({t_n, t_t, sigma_cr, tau_cr, mu});
  each_finite("t_n", b[0], b.size);
  each_finite("t_t", b[1], b.size);
  for (py::ssize_t i = 0; i < b.size; ++i) cl::validate_strength(b[2][i], b[3][i], b[4][i]);
  return b;
}

// 1-D parameter arrays of one length n (size-1 arrays are repeated).
std::vector<double> column(py::object a, std::size_t n, const char* name) {
  Arr arr(py::module_::import("numpy").attr("ravel")(a));
  const std::size_t m = static_cast<std::size_t>(arr.size());
  if (m != 1 && m != n) throw py::value_error(std::string(name) + " must have 1 or " +
                                              std::to_string(n) + " entries, got " +
                                              std::to_string(m));
  std::vector<double> v(n);
  for (std::size_t i = 0; i < n; ++i) v[i] = arr.data()[m == 1 ? 0 : i];
  return v;
}

std::size_t common_length(const std::vector<py::object>& args) {
  std::size_t n = 1;
  for (const auto& a : args) {
    const std::size_t m = static_cast<std::size_t>(Arr(a).size());
    if (m != 1) {
      if (n != 1 && m != n) throw py::value_error("parameter arrays must have equal lengths (or 1)");
      n = m;
    }
  }
  return n;
}

Arr openings(py::object a, std::size_t n, const char* name) {
  Arr arr(py::module_::import("numpy").attr("ravel")(a));
  if (static_cast<std::size_t>(arr.size()) != n)
    throw py::value_error(std::string(name) + " must have one entry per bond point (" +
                          std::to_string(n) + "), got " + std::to_string(arr.size()));
  return arr;
}

// (T, N) path arrays, row t the opening at the end of step t.
std::pair<Arr, Arr> paths(py::object dn, py::object dt, std::size_t n) {
  Arr a(dn), b(dt);
  if (a.ndim() != 2 || b.ndim() != 2 || a.shape(0) != b.shape(0) ||
      static_cast<std::size_t>(a.shape(1)) != n || static_cast<std::size_t>(b.shape(1)) != n)
    throw py::value_error("delta_n and delta_t paths must both have shape (steps, " +
                          std::to_string(n) + ")");
  return {a, b};
}

template <class T>
py::array_t<T> to_numpy(const std::vector<T>& v) {
  return py::array_t<T>(static_cast<py::ssize_t>(v.size()), v.data());
}

}  // namespace

// out[i] = f(i) over a broadcast: the loop every elementwise binding shares.
template <class F>
Arr elementwise(const Broadcast& b, F&& f) {
  Arr out = b.out();
  double* o = out.mutable_data();
  for (py::ssize_t i = 0; i < b.size; ++i) o[i] = f(i);
  return out;
}

// What a step of the initially-elastic bond points returns to Python.
py::dict elastic_result(const Arr& fn, const Arr& ft, const Arr& dis,
                        const py::array_t<std::int8_t>& ini, const py::array_t<std::int8_t>& failed) {
  py::dict r;
  r["f_n"] = fn;
  r["f_t"] = ft;
  r["dissipation"] = dis;
  r["initiated"] = ini.attr("astype")("bool");
  r["failed"] = failed.attr("astype")("bool");
  return r;
}

PYBIND11_MODULE(_cohesive_law, m) {
  m.doc() = "Freeze-bond cohesive law (Polojärvi & Tuhkuri 2013, eqs 5-12): mixed-mode "
            "criterion, linear softening, initially elastic variant. See docs/cohesive_law.md.";
  m.def("version", &cl::version);

  m.def("effective_traction",
        [](py::object t_n, py::object t_t, py::object sigma_cr, py::object tau_cr, py::object mu) {
          const Broadcast b = traction_args(t_n, t_t, sigma_cr, tau_cr, mu);
          return elementwise(b, [&](py::ssize_t i) {
            return cl::effective_traction(b[0][i], b[1][i], b[3][i] / b[2][i], b[4][i]);
          });
        },
        py::arg("t_n"), py::arg("t_t"), py::arg("sigma_cr"), py::arg("tau_cr"), py::arg("mu"),
        "Effective traction t_e of eq 6 [Pa].");

  m.def("criterion_reached",
        [](py::object t_n, py::object t_t, py::object sigma_cr, py::object tau_cr, py::object mu) {
          const Broadcast b = traction_args(t_n, t_t, sigma_cr, tau_cr, mu);
          auto out = b.out_bool();
          bool* o = out.mutable_data();
          for (py::ssize_t i = 0; i < b.size; ++i)
            o[i] = cl::criterion_reached(b[0][i], b[1][i], b[2][i], b[3][i], b[4][i]);
          return out;
        },
        py::arg("t_n"), py::arg("t_t"), py::arg("sigma_cr"), py::arg("tau_cr"), py::arg("mu"),
        "Eq 5: True where t_e >= sigma_cr.");

  m.def("effective_opening",
        [](py::object dn, py::object dt, py::object beta) {
          Broadcast b({dn, dt, beta});
          each_positive("beta", b[2], b.size);
          return elementwise(b, [&](py::ssize_t i) {
            return cl::effective_opening(b[0][i], b[1][i], b[2][i]);
          });
        },
        py::arg("delta_n"), py::arg("delta_t"), py::arg("beta"), "Eq 9 [m].");

  m.def("initial_force_magnitude",
        [](py::object mp, py::object mm, py::object fpx, py::object fpy, py::object fmx,
           py::object fmy) {
          Broadcast b({mp, mm, fpx, fpy, fmx, fmy});
          each_positive("m_plus", b[0], b.size);
          each_positive("m_minus", b[1], b.size);
          return elementwise(b, [&](py::ssize_t i) {
            return cl::initial_force_magnitude(b[0][i], b[1][i], b[2][i], b[3][i], b[4][i], b[5][i]);
          });
        },
        py::arg("m_plus"), py::arg("m_minus"), py::arg("f_plus_x"), py::arg("f_plus_y"),
        py::arg("f_minus_x"), py::arg("f_minus_y"), "Eq 8: |f_c^0| [N/m].");

  m.def("initial_effective_force",
        [](py::object fn, py::object ft, py::object beta, const std::string& direction) {
          const cl::ForceDirection dir = cl::parse_direction(direction);
          Broadcast b({fn, ft, beta});
          each_positive("beta", b[2], b.size);
          return elementwise(b, [&](py::ssize_t i) {
            return cl::initial_effective_force(b[0][i], b[1][i], b[2][i], dir);
          });
        },
        py::arg("f_n"), py::arg("f_t"), py::arg("beta"), py::arg("direction") = "paper");

  m.def("critical_opening",
        [](py::object G, py::object l, py::object f0) {
          Broadcast b({G, l, f0});
          each_positive("G", b[0], b.size);
          each_positive("l", b[1], b.size);
          each_positive("f0", b[2], b.size);
          return elementwise(b, [&](py::ssize_t i) {
            return cl::critical_opening(b[0][i], b[1][i], b[2][i]);
          });
        },
        py::arg("G"), py::arg("l"), py::arg("f0"), "Eq 12: delta_f = 2 G l / f0 [m].");

  m.def("failure_mode",
        [](py::object dn, py::object dt) {
          Broadcast b({dn, dt});
          auto out = b.out_i8();
          std::int8_t* o = out.mutable_data();
          for (py::ssize_t i = 0; i < b.size; ++i)
            o[i] = static_cast<std::int8_t>(cl::failure_mode(b[0][i], b[1][i]));
          return out;
        },
        py::arg("delta_n"), py::arg("delta_t"), "1 tensile (delta_n >= |delta_t|), 2 shear.");

  m.def("work_increment",
        [](py::object fno, py::object fto, py::object fnn, py::object ftn, py::object ddn,
           py::object ddt) {
          Broadcast b({fno, fto, fnn, ftn, ddn, ddt});
          return elementwise(b, [&](py::ssize_t i) {
            return cl::work_increment(b[0][i], b[1][i], b[2][i], b[3][i], b[4][i], b[5][i]);
          });
        },
        py::arg("f_n_old"), py::arg("f_t_old"), py::arg("f_n_new"), py::arg("f_t_new"),
        py::arg("d_delta_n"), py::arg("d_delta_t"),
        "Trapezoid work 1/2 (f_old + f_new) . d_delta of one step [J/m].");

  m.def("stored_energy",
        [](py::object dn, py::object dt, py::object beta, py::object f0, py::object delta_f,
           py::object delta_m, const std::string& direction) {
          const cl::ForceDirection dir = cl::parse_direction(direction);
          Broadcast b({dn, dt, beta, f0, delta_f, delta_m});
          each_positive("beta", b[2], b.size);
          each_positive("f0", b[3], b.size);
          each_positive("delta_f", b[4], b.size);
          return elementwise(b, [&](py::ssize_t i) {
            return cl::stored_energy(b[0][i], b[1][i], b[2][i], b[3][i], b[4][i], b[5][i], dir);
          });
        },
        py::arg("delta_n"), py::arg("delta_t"), py::arg("beta"), py::arg("f0"),
        py::arg("delta_f"), py::arg("delta_m"), py::arg("direction") = "paper",
        "Energy given back along the secant by an opened bond point [J/m].");

  m.def("opening_components",
        [](py::object dx, py::object dy, py::object nx, py::object ny) {
          Broadcast b({dx, dy, nx, ny});
          Arr dn = b.out(), dt = b.out();
          double *a = dn.mutable_data(), *c = dt.mutable_data();
          for (py::ssize_t i = 0; i < b.size; ++i)
            cl::opening_components(b[0][i], b[1][i], b[2][i], b[3][i], a[i], c[i]);
          return py::make_tuple(dn, dt);
        },
        py::arg("dx"), py::arg("dy"), py::arg("n_x"), py::arg("n_y"),
        "(delta_n, delta_t) of the separation x+ - x- for the normal n (tangent (-n_y, n_x)).");

  m.def("nodal_forces",
        [](py::object fn, py::object ft, py::object nx, py::object ny) {
          Broadcast b({fn, ft, nx, ny});
          Arr px = b.out(), py_ = b.out(), mx = b.out(), my = b.out();
          double *a = px.mutable_data(), *c = py_.mutable_data(), *d = mx.mutable_data(),
                 *e = my.mutable_data();
          for (py::ssize_t i = 0; i < b.size; ++i)
            cl::nodal_forces(b[0][i], b[1][i], b[2][i], b[3][i], a[i], c[i], d[i], e[i]);
          return py::make_tuple(px, py_, mx, my);
        },
        py::arg("f_n"), py::arg("f_t"), py::arg("n_x"), py::arg("n_y"),
        "(f_plus_x, f_plus_y, f_minus_x, f_minus_y): f_plus = -f, f_minus = +f.");

  m.def("depth_factor",
        [](py::object depth, double keel_depth, double bottom_fraction) {
          cl::validate_depth_scaling(keel_depth, bottom_fraction);
          Broadcast b({depth});
          each_finite("depth", b[0], b.size);
          return elementwise(b, [&](py::ssize_t i) {
            return cl::depth_factor(b[0][i], keel_depth, bottom_fraction);
          });
        },
        py::arg("depth"), py::arg("keel_depth"), py::arg("bottom_fraction") = 0.1,
        "Factor on sigma_cr, tau_cr and G: 1 at the keel top, bottom_fraction at the bottom.");

  m.def("min_elastic_stiffness",
        [](double sigma_cr, double tau_cr, double G, double l, const std::string& direction) {
          const cl::ForceDirection dir = cl::parse_direction(direction);
          cl::validate_strength(sigma_cr, tau_cr, 0.0);
          cl::require_positive("G", G);
          cl::require_positive("l", l);
          return cl::min_elastic_stiffness(sigma_cr, tau_cr, G, l, dir);
        },
        py::arg("sigma_cr"), py::arg("tau_cr"), py::arg("G"), py::arg("l"),
        py::arg("direction") = "paper");

  py::class_<cl::OpenedBondPoints>(m, "OpenedBondPoints",
                                   "Opened bond points of the initially rigid law (eqs 9-12).")
      .def(py::init([](py::object f0, py::object G, py::object l, py::object beta,
                       const std::string& direction) {
             const cl::ForceDirection dir = cl::parse_direction(direction);
             const std::size_t n = common_length({f0, G, l, beta});
             auto vf0 = column(f0, n, "f0"), vG = column(G, n, "G"), vl = column(l, n, "l"),
                  vb = column(beta, n, "beta");
             for (std::size_t i = 0; i < n; ++i) {  // validate all before building
               cl::require_positive("f0", vf0[i]);
               cl::require_positive("G", vG[i]);
               cl::require_positive("l", vl[i]);
               cl::require_positive("beta", vb[i]);
             }
             cl::OpenedBondPoints b(dir);
             for (std::size_t i = 0; i < n; ++i) b.add(vf0[i], vG[i], vl[i], vb[i]);
             return b;
           }),
           py::arg("f0"), py::arg("G"), py::arg("l"), py::arg("beta"), py::arg("direction") = "paper")
      .def("__len__", &cl::OpenedBondPoints::size)
      .def("step",
           [](cl::OpenedBondPoints& b, py::object dn, py::object dt) {
             const std::size_t n = b.size();
             Arr a = openings(dn, n, "delta_n"), c = openings(dt, n, "delta_t");
             Arr fn(n), ft(n), dis(n);
             py::array_t<std::int8_t> failed(n);
             b.step(a.data(), c.data(), fn.mutable_data(), ft.mutable_data(), dis.mutable_data(),
                    failed.mutable_data());
             py::dict r;
             r["f_n"] = fn; r["f_t"] = ft; r["dissipation"] = dis;
             r["failed"] = failed.attr("astype")("bool");
             return r;
           },
           py::arg("delta_n"), py::arg("delta_t"),
           "Advance to the openings at the end of the step; returns f_n, f_t, dissipation, failed.")
      .def("run_path",
           [](cl::OpenedBondPoints& b, py::object dn, py::object dt) {
             const std::size_t n = b.size();
             auto [a, c] = paths(dn, dt, n);
             const py::ssize_t T = a.shape(0), N = static_cast<py::ssize_t>(n);
             Arr fn({T, N}), ft({T, N}), dis({T, N});
             py::array_t<std::int8_t> failed({T, N});
             for (py::ssize_t t = 0; t < T; ++t)
               b.step(a.data() + t * N, c.data() + t * N, fn.mutable_data() + t * N,
                      ft.mutable_data() + t * N, dis.mutable_data() + t * N,
                      failed.mutable_data() + t * N);
             py::dict r;
             r["f_n"] = fn; r["f_t"] = ft; r["dissipation"] = dis;
             r["failed"] = failed.attr("astype")("bool");
             return r;
           },
           py::arg("delta_n"), py::arg("delta_t"),
           "step() along (steps, N) paths; returns (steps, N) arrays.")
      .def_property_readonly("direction", [](const cl::OpenedBondPoints& b) { return cl::direction_name(b.direction); })
      .def_property_readonly("f0", [](const cl::OpenedBondPoints& b) { return to_numpy(b.f0); })
      .def_property_readonly("beta", [](const cl::OpenedBondPoints& b) { return to_numpy(b.beta); })
      .def_property_readonly("delta_f", [](const cl::OpenedBondPoints& b) { return to_numpy(b.delta_f); })
      .def_property_readonly("delta_m", [](const cl::OpenedBondPoints& b) { return to_numpy(b.delta_m); })
      .def_property_readonly("mode", [](const cl::OpenedBondPoints& b) { return to_numpy(b.mode); })
      .def_property_readonly("broken", [](const cl::OpenedBondPoints& b) {
        py::array_t<bool> o(static_cast<py::ssize_t>(b.size()));
        for (std::size_t i = 0; i < b.size(); ++i) o.mutable_data()[i] = b.broken(i);
        return o;
      });

  py::class_<cl::ElasticBondPoints>(m, "ElasticBondPoints",
                                    "Initially elastic bond points for rigid blocks.")
      .def(py::init([](py::object k, py::object l, py::object sigma_cr, py::object tau_cr,
                       py::object mu, py::object G, const std::string& direction) {
             const cl::ForceDirection dir = cl::parse_direction(direction);
             const std::size_t n = common_length({k, l, sigma_cr, tau_cr, mu, G});
             auto vk = column(k, n, "k"), vl = column(l, n, "l"), vs = column(sigma_cr, n, "sigma_cr"),
                  vt = column(tau_cr, n, "tau_cr"), vm = column(mu, n, "mu"), vG = column(G, n, "G");
             cl::ElasticBondPoints b(dir);
             for (std::size_t i = 0; i < n; ++i) b.add({vk[i], vl[i], vs[i], vt[i], vm[i], vG[i]});
             return b;
           }),
           py::arg("k"), py::arg("l"), py::arg("sigma_cr"), py::arg("tau_cr"), py::arg("mu"),
           py::arg("G"), py::arg("direction") = "paper")
      .def("__len__", &cl::ElasticBondPoints::size)
      .def("step",
           [](cl::ElasticBondPoints& b, py::object dn, py::object dt) {
             const std::size_t n = b.size();
             Arr a = openings(dn, n, "delta_n"), c = openings(dt, n, "delta_t");
             Arr fn(n), ft(n), dis(n);
             py::array_t<std::int8_t> ini(n), failed(n);
             b.step(a.data(), c.data(), fn.mutable_data(), ft.mutable_data(), dis.mutable_data(),
                    ini.mutable_data(), failed.mutable_data());
             return elastic_result(fn, ft, dis, ini, failed);
           },
           py::arg("delta_n"), py::arg("delta_t"))
      .def("run_path",
           [](cl::ElasticBondPoints& b, py::object dn, py::object dt) {
             const std::size_t n = b.size();
             auto [a, c] = paths(dn, dt, n);
             const py::ssize_t T = a.shape(0), N = static_cast<py::ssize_t>(n);
             Arr fn({T, N}), ft({T, N}), dis({T, N});
             py::array_t<std::int8_t> ini({T, N}), failed({T, N});
             for (py::ssize_t t = 0; t < T; ++t)
               b.step(a.data() + t * N, c.data() + t * N, fn.mutable_data() + t * N,
                      ft.mutable_data() + t * N, dis.mutable_data() + t * N,
                      ini.mutable_data() + t * N, failed.mutable_data() + t * N);
             return elastic_result(fn, ft, dis, ini, failed);
           },
           py::arg("delta_n"), py::arg("delta_t"))
      .def("stored_energy",
           [](const cl::ElasticBondPoints& b) {
             Arr o(static_cast<py::ssize_t>(b.size()));
             for (std::size_t i = 0; i < b.size(); ++i) o.mutable_data()[i] = b.stored_energy(i);
             return o;
           },
           "Recoverable energy of each bond point at its last opening [J/m].")
      .def_property_readonly("direction", [](const cl::ElasticBondPoints& b) { return cl::direction_name(b.direction); })
      .def_property_readonly("state", [](const cl::ElasticBondPoints& b) { return to_numpy(b.state); })
      .def_property_readonly("mode", [](const cl::ElasticBondPoints& b) { return to_numpy(b.mode); })
      .def_property_readonly("f0", [](const cl::ElasticBondPoints& b) { return to_numpy(b.f0); })
      .def_property_readonly("delta_f", [](const cl::ElasticBondPoints& b) { return to_numpy(b.delta_f); })
      .def_property_readonly("delta_m", [](const cl::ElasticBondPoints& b) { return to_numpy(b.delta_m); })
      .def_property_readonly("delta_0", [](const cl::ElasticBondPoints& b) { return to_numpy(b.delta_0); })
      .def_property_readonly("peak_f_n", [](const cl::ElasticBondPoints& b) { return to_numpy(b.peak_f_n); })
      .def_property_readonly("peak_f_t", [](const cl::ElasticBondPoints& b) { return to_numpy(b.peak_f_t); });

  m.attr("TENSILE") = static_cast<int>(cl::FailureMode::tensile);
  m.attr("SHEAR") = static_cast<int>(cl::FailureMode::shear);
}
