// Python access to the GPU backend (cuda/body_forces.hpp); in a build without
// CUDA the same names exist and say there is no GPU backend.
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <cmath>

#include "bindings/bindings.hpp"
#include "contact/broad_phase.hpp"
#include "contact/candidate_layout.hpp"
#include "cuda/body_forces.hpp"
#include "cuda/broad_phase.hpp"
#include "cuda/bond_check.hpp"
#include "cuda/cohesive_forces.hpp"
#include "cuda/contact_normal.hpp"
#include "cuda/device_memory.hpp"
#include "cuda/device_step.hpp"
#include "cuda/emulation_check.hpp"
#include "cuda/friction.hpp"
#include "cuda/node_update.hpp"
#include "model/model.hpp"

namespace py = pybind11;

namespace engine {

namespace {

py::dict as_dict(const BodyForceFields& f) {
  py::dict d;
  d["f_int_x"] = as_array(f.f_int_x);
  d["f_int_y"] = as_array(f.f_int_y);
  d["f_visc_x"] = as_array(f.f_visc_x);
  d["f_visc_y"] = as_array(f.f_visc_y);
  d["f_buoy_y"] = as_array(f.f_buoy_y);
  d["drag_k"] = as_array(f.drag_k);
  d["stress"] = as_array(f.stress);
  d["energy"] = as_array(f.energy);
  d["elastic_energy"] = f.elastic_energy;
  d["first_inverted"] = f.first_inverted;
  return d;
}

// The CPU's fields of the same stage, from the model's last force evaluation.
BodyForceFields cpu_fields(const Model& m) {
  const Nodes& N = m.nodes();
  const Triangles& T = m.triangles();
  BodyForceFields f;
  f.f_int_x = N.f_int_x;
  f.f_int_y = N.f_int_y;
  f.f_visc_x = N.f_visc_x;
  f.f_visc_y = N.f_visc_y;
  f.f_buoy_y = N.f_buoy_y;
  f.drag_k = N.drag_k;
  f.stress = T.stress;
  f.energy = T.energy;
  f.elastic_energy = m.energy().elastic;
  return f;
}

py::dict as_dict(const BondCheckFields& f) {
  py::dict d;
  d["ratio"] = as_array(f.ratio);
  d["tn"] = as_array(f.tn);
  d["tt"] = as_array(f.tt);
  d["plan"] = as_array(f.plan);
  return d;
}

// The CPU's bond check at the model's state now: the same kernel over every
// intact point (no screening), into buffers of its own, so the model and its
// bonds are left as they were.
BondCheckFields cpu_bond_check(const Model& model) {
  const FreezeBonds& B = model.bonds();
  BondCheckFields f;
  f.ratio.assign(size_t(B.n_points()), NAN);
  f.tn.assign(size_t(B.n_pairs()), NAN);
  f.tt.assign(size_t(B.n_pairs()), NAN);
  BondCheckArrays a = B.check_arrays(model);
  a.tn = f.tn.data();
  a.tt = f.tt.data();
  const double mu = B.mu(model);
  for (int32_t p : B.intact_points()) {
    f.ratio[p] = bond_point_ratio(a, p, mu);
    if (f.ratio[p] >= 1.0) f.plan.push_back(p);
  }
  return f;
}

py::dict as_dict(const CohesiveForceFields& f) {
  py::dict d;
  d["f_coh_x"] = as_array(f.f_coh_x);
  d["f_coh_y"] = as_array(f.f_coh_y);
  d["fpx"] = as_array(f.fpx);
  d["fpy"] = as_array(f.fpy);
  d["delta_m"] = as_array(f.delta_m);
  d["failed"] = as_array(f.failed);
  d["mode"] = as_array(f.mode);
  d["work"] = f.work;
  d["stored"] = f.stored;
  d["dissipation"] = f.dissipation;
  return d;
}

// The CPU's cohesive forces at the model's state now: the same kernel over
// the opened pairs, scattered in pair order as FreezeBonds::apply does, into
// buffers of its own (the pairs' history is left as it was).
CohesiveForceFields cpu_cohesive_forces(const Model& model) {
  const FreezeBonds& B = model.bonds();
  const CohesivePairArrays a = B.pair_arrays(model);
  const size_t nn = size_t(model.nodes().size());
  CohesiveForceFields f;
  f.f_coh_x.assign(nn, 0.0);
  f.f_coh_y.assign(nn, 0.0);
  for (int32_t k : B.open_pairs()) {
    const CohesivePairStep r = cohesive_pair_step(a, k, B.params().direction, model.dt());
    f.fpx.push_back(r.fpx);
    f.fpy.push_back(r.fpy);
    f.delta_m.push_back(r.delta_m);
    f.failed.push_back(int8_t(r.failed));
    f.mode.push_back(r.mode);
    f.f_coh_x[size_t(a.node_plus[k])] += r.fpx;
    f.f_coh_y[size_t(a.node_plus[k])] += r.fpy;
    f.f_coh_x[size_t(a.node_minus[k])] -= r.fpx;
    f.f_coh_y[size_t(a.node_minus[k])] -= r.fpy;
    f.work += r.work;
    f.stored += r.stored;
    f.dissipation += r.dissipation;
  }
  return f;
}

}  // namespace

void bind_device(py::module_& m) {
  m.def("cuda_built", &cuda_built, "whether this build has the GPU backend");
  m.def("cuda_emulated", &cuda_emulated,
        "whether this build has the GPU backend on the CPU emulation of the CUDA runtime (no toolkit; for tests)");
  m.def("cuda_emulation_check", &cuda_emulation_check, py::arg("scene"),
        "one of the emulated runtime's self-checks (cuda/emulation/self_check.cpp): its numbers by name");
  m.def("cuda_device", &cuda_device_name, "the GPU the backend sees ('' if none)");
  m.def("device_memory_counts", [] {
    const DeviceMemoryCounts c = device_memory_counts();
    py::dict d;
    d["allocations"] = c.allocations;
    d["reuses"] = c.reuses;
    d["waits"] = c.waits;
    d["cached_bytes"] = c.cached_bytes;
    d["used_bytes"] = c.used_bytes;
    return d;
  }, "the GPU memory blocks of this process (cuda/device_memory.hpp): allocated fresh, reused from the cache, "
     "device waits before a reuse, bytes cached and in use");
  m.def("device_size_class", &device_size_class, py::arg("bytes"),
        "the block size a request of `bytes` GPU memory is given (cuda/device_memory.hpp)");
  m.def("body_force_fields", [](const Model& model) { return as_dict(cpu_fields(model)); },
        "the CPU's body-force fields of the model's last evaluation (what DeviceBodyForces computes)");
  m.def("contact_fields", [](const Model& model) {
        py::dict d;
        d["f_con_x"] = as_array(model.nodes().f_con_x);
        d["f_con_y"] = as_array(model.nodes().f_con_y);
        d["energy"] = model.contact().stored_energy();
        d["touching"] = model.contact().touching_pairs();
        return d;
      }, "the CPU's normal contact fields of the model's last evaluation (what DeviceContactNormal computes)");
  m.def("friction_fields", [](const Model& model) {
        const Nodes& N = model.nodes();
        py::dict d;
        d["f_x"] = as_array(N.f_x);
        d["f_y"] = as_array(N.f_y);
        d["lambda"] = as_array(model.contact().friction_forces());
        d["power"] = model.contact().friction_power();
        const FrictionOrder& o = model.contact().sweep_order();
        std::vector<int32_t> colour(o.pair.size());
        for (int32_t c = 0; c < o.colours(); ++c)
          for (int32_t k = o.colour_start[c]; k < o.colour_start[c + 1]; ++k) colour[size_t(o.pair[k])] = c;
        d["colour"] = as_array(colour);
        d["colours"] = o.colours();
        d["constrained"] = as_array(N.constrained);
        return d;
      }, "the CPU's friction of the model's last evaluation (what DeviceFriction computes); f_x, f_y after "
         "the boundary conditions, so compare the components that are not prescribed");
  m.def("bond_check_fields", [](const Model& model) { return as_dict(cpu_bond_check(model)); },
        "the CPU's bond check at the model's state now, every intact point (what DeviceBondCheck computes)");
  m.def("cohesive_fields", [](const Model& model) { return as_dict(cpu_cohesive_forces(model)); },
        "the CPU's cohesive forces at the model's state now, every opened pair (what DeviceCohesiveForces "
        "computes)");
  py::class_<DeviceCohesiveForces>(m, "DeviceCohesiveForces")
      .def(py::init<const Model&>(), py::arg("model"))
      .def("run", &DeviceCohesiveForces::run)
      .def("time_per_run", &DeviceCohesiveForces::time_per_run, py::arg("repeats"),
           py::call_guard<py::gil_scoped_release>())
      .def_property_readonly("open_pairs", &DeviceCohesiveForces::open_pairs)
      .def("fields", [](DeviceCohesiveForces& d) { return as_dict(d.fields()); });
  py::class_<DeviceBondCheck>(m, "DeviceBondCheck")
      .def(py::init<const Model&>(), py::arg("model"))
      .def("run", &DeviceBondCheck::run)
      .def("time_per_run", &DeviceBondCheck::time_per_run, py::arg("repeats"),
           py::call_guard<py::gil_scoped_release>())
      .def("fields", [](DeviceBondCheck& d) { return as_dict(d.fields()); });
  py::class_<DeviceBodyForces>(m, "DeviceBodyForces")
      .def(py::init<const Model&>(), py::arg("model"))
      .def("upload_state", &DeviceBodyForces::upload_state)
      .def("run", &DeviceBodyForces::run)
      .def("time_per_run", &DeviceBodyForces::time_per_run, py::arg("repeats"),
           py::call_guard<py::gil_scoped_release>())
      .def("stage_times", &DeviceBodyForces::stage_times, py::arg("repeats"),
           py::call_guard<py::gil_scoped_release>())
      .def("fields", [](DeviceBodyForces& d) { return as_dict(d.fields()); });
  py::class_<DeviceBroadPhase>(m, "DeviceBroadPhase")
      .def(py::init<const Model&>(), py::arg("model"))
      .def("search", [](DeviceBroadPhase& d, const Model& model) {
             const SearchedLayout L = d.search(model);
             py::dict out;
             out["node"] = as_array(L.node);
             out["key"] = as_array(L.key);
             out["start"] = as_array(L.start);
             out["entry"] = as_array(L.entry);
             out["skin"] = L.skin;
             return out;
           }, py::arg("model"))
      .def("seconds_per_search", &DeviceBroadPhase::seconds_per_search, py::arg("model"), py::arg("repeats"),
           py::call_guard<py::gil_scoped_release>());
  m.def("broad_phase_layout", [](const Model& model) {
        // the CPU's search at the model's positions now (BroadPhase::find with
        // its solver's skin fraction), laid out as the GPU's contact stages
        // read it: what DeviceBroadPhase.search finds on the GPU
        const std::vector<int32_t>& surface = model.surface_triangles();
        const std::vector<int32_t>& tri = model.triangles().node;
        BroadPhase bp;
        std::vector<CandidatePair> cand;
        bp.find(int32_t(surface.size()), surface.data(), tri.data(), model.triangles().body.data(),
                model.nodes().x.data(), model.nodes().y.data(), cand, 1, model.contact().skin_fraction());
        CandidateLayout L;
        lay_out_candidates(cand, tri.data(), int32_t(model.nodes().size()), L);
        py::dict out;
        out["node"] = as_array(L.node);
        out["key"] = as_array(L.key);
        out["start"] = as_array(L.start);
        out["entry"] = as_array(L.entry);
        out["skin"] = bp.skin();
        return out;
      }, "the CPU's candidate search at the model's positions, laid out (what DeviceBroadPhase.search finds)");
  py::class_<DeviceContactNormal>(m, "DeviceContactNormal")
      .def(py::init<const Model&>(), py::arg("model"))
      .def("run", &DeviceContactNormal::run)
      .def("time_per_run", &DeviceContactNormal::time_per_run, py::arg("repeats"),
           py::call_guard<py::gil_scoped_release>())
      .def_property_readonly("candidates", &DeviceContactNormal::candidates)
      .def("fields", [](DeviceContactNormal& d) {
        const ContactNormalFields f = d.fields();
        py::dict out;
        out["f_con_x"] = as_array(f.f_con_x);
        out["f_con_y"] = as_array(f.f_con_y);
        out["energy"] = f.energy;
        out["touching"] = f.touching;
        return out;
      });
  py::class_<DeviceFriction>(m, "DeviceFriction")
      .def(py::init<const Model&>(), py::arg("model"))
      .def("run", &DeviceFriction::run)
      .def("time_per_run", &DeviceFriction::time_per_run, py::arg("repeats"),
           py::call_guard<py::gil_scoped_release>())
      .def_property_readonly("candidates", &DeviceFriction::candidates)
      .def("set_earlier_list", &DeviceFriction::set_earlier_list, py::arg("n"))
      .def("set_shared_nodes", &DeviceFriction::set_shared_nodes, py::arg("n"))
      .def("fields", [](DeviceFriction& d) {
        const FrictionFields f = d.fields();
        py::dict out;
        out["f_x"] = as_array(f.f_x);
        out["f_y"] = as_array(f.f_y);
        out["lambda"] = as_array(f.lambda);
        out["power"] = f.power;
        out["colour"] = as_array(f.colour);
        out["colours"] = f.colours;
        out["rounds"] = f.rounds;
        out["colourings"] = f.colourings;
        out["local_nodes"] = f.local_nodes;
        return out;
      });
  py::class_<DeviceStep>(m, "DeviceStep")
      .def(py::init<Model&>(), py::arg("model"))
      .def("step", &DeviceStep::step, py::arg("n"), py::call_guard<py::gil_scoped_release>())
      .def("download", &DeviceStep::download, py::arg("model"))
      .def("reaction", [](DeviceStep& d, const std::vector<int32_t>& nodes) {
             double rx = 0.0, ry = 0.0;
             d.reaction(nodes, rx, ry);
             return py::make_tuple(rx, ry);
           }, py::arg("nodes"))
      .def_property_readonly("time", &DeviceStep::time)
      .def_property_readonly("step_count", &DeviceStep::step_count)
      .def_property_readonly("host_steps", &DeviceStep::host_steps)
      .def_property_readonly("remakes", &DeviceStep::remakes)
      .def_property_readonly("host_step_seconds", &DeviceStep::host_step_seconds)
      .def_property_readonly("make_seconds", &DeviceStep::make_seconds)
      .def_property_readonly("list_rebuilds", &DeviceStep::list_rebuilds)
      .def_property_readonly("graph_instantiations", &DeviceStep::graph_instantiations)
      .def_property_readonly("graph_updates", &DeviceStep::graph_updates)
      .def_property_readonly("colourings", &DeviceStep::colourings)
      .def_property_readonly("list_seconds", &DeviceStep::list_seconds);
  py::class_<DeviceNodeUpdate>(m, "DeviceNodeUpdate")
      .def(py::init<const Model&>(), py::arg("model"))
      .def("run", &DeviceNodeUpdate::run)
      .def("time_per_run", &DeviceNodeUpdate::time_per_run, py::arg("repeats"),
           py::call_guard<py::gil_scoped_release>())
      .def("fields", [](DeviceNodeUpdate& d) {
        const NodeUpdateFields f = d.fields();
        py::dict out;
        out["x"] = as_array(f.x);
        out["y"] = as_array(f.y);
        out["vx"] = as_array(f.vx);
        out["vy"] = as_array(f.vy);
        out["sums"] = as_array(f.sums);
        return out;
      });
}

}  // namespace engine
