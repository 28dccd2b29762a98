// The force stages of a step, (1)-(6) of docs/model.md §3, each adding into
// the node arrays in a fixed order (bit-reproducible at a fixed thread count).
#include "common/input_errors.hpp"
#include "model/model.hpp"
#include "model/assemble_kernel.hpp"

#include <omp.h>

#include <algorithm>

#include "common/stopwatch.hpp"
#include "model/threading.hpp"

namespace engine {

// The gather's arrays (model/gather_kernel.hpp): the per-node sums of the
// corner forces (elastic, viscous, buoyancy) and the drag coefficient, in the
// fixed gather order, plus gravity and drag.
GatherArrays Model::gather_arrays(bool damping, bool water, bool buoy, bool drag, double g) {
  Nodes& N = nodes_;
  return {gather_.start.data(), gather_.slot.data(), N.vx.data(),
          N.vy.data(), N.mass_phys.data(), N.f_int_x.data(), N.f_int_y.data(), N.f_visc_x.data(),
          N.f_visc_y.data(), N.f_buoy_y.data(), N.drag_k.data(), N.f_x.data(), N.f_y.data(),
          N.f_coh_x.data(), N.f_coh_y.data(), damping, water, buoy, drag, g};
}

// A node's total of everything but contact, bonds and friction; also used
// for a node that has just been split off (FreezeBonds::split_points).
void Model::gather_node(int32_t i, bool damping, bool water, bool buoy, bool drag, double g) {
  gather_node_loads(gather_arrays(damping, water, buoy, drag, g), CornerRecords{tris_.corner_load.data()}, i);
}

void Model::compute_body_forces() {
  Stopwatch sw(timings_.elements);
  const int nt = int(partial_.size());
  const int32_t m = tris_.size(), n = nodes_.size();
  int32_t inverted[kMaxThreads];
  std::fill(inverted, inverted + kMaxThreads, -1);
  const bool damping = any_damping_;
  const bool water = params_.external.water();
  const bool buoy = params_.external.buoyancy, drag = params_.external.drag_on();
  const double g = params_.external.gravity ? params_.external.g : 0.0;
  if (drag) {
    Stopwatch drag_sw(timings_.drag);
    body_drag_constants(nodes_, params_.external, body_area0_, body_drag_, body_tris_, use_threads() ? nt : 1);
  }
  // Sleeping far field: only the listed triangles are computed; the others
  // keep their stored (exact, frozen) forces and energies.
  const bool sleeping = params_.sleep.on && !compute_all_next_;
  compute_all_next_ = false;
  if (sleeping) rebuild_awake_triangles();
  const int32_t* list = sleeping ? awake_tris_.data() : nullptr;
  const int32_t n_computed = sleeping ? int32_t(awake_tris_.size()) : m;
  timings_.element_steps += n_computed;
  const bool threaded = use_threads();
  const int team_size = threaded ? nt : 1;
  if (!sleeping && (gather_plan_.topology != topology_version_ || gather_plan_.threads != team_size))
    gather_plan_.build(tris_, gather_, n, team_size, topology_version_);
  Nodes& N = nodes_;
  // a node's sums of this step's corner loads; the contact and cohesive passes add into f_con
  const GatherArrays gathered = gather_arrays(damping, water, buoy, drag, g);
  const CornerRecords corners{tris_.corner_load.data()};
  const auto gather = [&](int32_t i) {
    gather_node_loads(gathered, corners, i);
    N.f_con_x[i] = N.f_con_y[i] = 0.0;
  };
  if (timings_.element_busy.size() < size_t(team_size)) {
    timings_.element_busy.resize(size_t(team_size), 0.0);
    timings_.element_wait.resize(size_t(team_size), 0.0);
  }
  double* busy = timings_.element_busy.data();
  double* wait = timings_.element_wait.data();
  #pragma omp parallel num_threads(nt) if (threaded)
  {
    const double t_start = omp_get_wtime();
    const int tid = omp_get_thread_num(), team = omp_get_num_threads();
    // With every triangle computed, each node is gathered in the element pass
    // once its last corner is computed (gather_plan.hpp).
    const bool in_pass = !sleeping && team == gather_plan_.threads;
    int32_t b, e;
    block(n_computed, tid, team, b, e);
    // (1) element forces and (6) water forces, per triangle.
    ElementSweep sweep;
    if (in_pass) {
      const GatherPlan& P = gather_plan_;
      for (int32_t c = P.thread_chunk[tid]; c < P.thread_chunk[tid + 1]; ++c) {
        element_forces(nodes_, tris_, elem_mat_, damping, P.chunk_begin[c], P.chunk_end[c], sweep);
        if (water) water_forces_on_triangles(nodes_, tris_, params_.external, body_area0_, body_drag_, P.chunk_begin[c], P.chunk_end[c]);
        for (int32_t k = P.node_start[c]; k < P.node_start[c + 1]; ++k) gather(P.nodes[k]);
      }
    } else {
      element_forces(nodes_, tris_, elem_mat_, damping, b, e, sweep, list);
      if (water) water_forces_on_triangles(nodes_, tris_, params_.external, body_area0_, body_drag_, b, e, list);
    }
    partial_[tid].s.elastic = sweep.elastic_energy;
    inverted[tid] = sweep.inverted;
    const double t_done = omp_get_wtime();
    #pragma omp barrier
    busy[tid] += t_done - t_start;
    wait[tid] += omp_get_wtime() - t_done;
    if (sleeping) {
      // the strain energy of every triangle, the sleeping ones' as stored
      block(m, tid, team, b, e);
      double u = 0.0;
      for (int32_t t = b; t < e; ++t) u += tris_.energy[t];
      partial_[tid].s.elastic = u;
    }
    // Gather corner forces onto nodes in the fixed gather order, add gravity
    // and drag: the total of everything but contact, bonds and friction.
    if (in_pass) {
      const std::vector<int32_t>& late = gather_plan_.straddling;
      #pragma omp for schedule(static)
      for (size_t k = 0; k < late.size(); ++k) gather(late[k]);
    } else {
      #pragma omp for schedule(static)
      for (int32_t i = 0; i < n; ++i) gather(i);
    }
  }
  double u = 0.0;
  first_inverted_ = -1;
  for (int t = 0; t < nt; ++t) {
    u += partial_[t].s.elastic;
    partial_[t].s.elastic = 0.0;
    if (first_inverted_ < 0) first_inverted_ = inverted[t];
  }
  energy_.elastic = u;
}

ContactInput Model::contact_input() const {
  ContactInput in;
  in.n_nodes = nodes_.size();
  in.x = nodes_.x.data();
  in.y = nodes_.y.data();
  in.vx = nodes_.vx.data();
  in.vy = nodes_.vy.data();
  in.mass = nodes_.mass.data();
  in.n_tri = tris_.size();
  in.tri = tris_.node.data();
  in.body = tris_.body.data();
  in.n_surface = int32_t(surface_tris_.size());
  in.surface_tris = surface_tris_.data();
  in.dt = dt_;
  in.threads = params_.threads;
  in.topology_version = topology_version_;
  // Friction must see fixed and driven nodes as immovable (contact branch).
  in.constrained = nodes_.constrained.data();
  return in;
}

// The same in the reference configuration: the stable step and the mass
// scaling are taken there, so they depend on the mesh (and its splits) alone,
// not on when they are computed (a resumed run gets the same).
ContactInput Model::reference_contact_input() const {
  ContactInput in = contact_input();
  in.x = nodes_.x0.data();
  in.y = nodes_.y0.data();
  return in;
}

// Taken again only where the penalty, the reach or the mesh's corners changed
// otherwise than by bond splits: a split renames a (node, body) entry
// (rename_contact_shares), where taking it again walked the whole mesh's
// boundaries (most of a split step's cost on the paper mesh).
const ContactStiffness& Model::reference_contact_stiffness() {
  if (ref_stiffness_stale_ || ref_stiffness_reach_ != params_.contact_reach ||
      ref_stiffness_penalty_ != params_.contact.penalty) {
    ref_stiffness_ = contact_stiffness(params_.contact, reference_contact_input(), params_.contact_reach);
    ref_stiffness_stale_ = false;
    ref_stiffness_reach_ = params_.contact_reach;
    ref_stiffness_penalty_ = params_.contact.penalty;
  } else if (!ref_stiffness_renames_.empty()) {
    rename_contact_shares(ref_stiffness_, ref_stiffness_renames_, reference_contact_input());
  }
  ref_stiffness_renames_.clear();
  return ref_stiffness_;
}

void Model::build_contact_list() { contact_.build_list(contact_input()); }

void Model::compute_contact_forces() {
  contact_work_step_ = 0.0;
  if (!contact_possible_) return;
  const double detection_before = contact_.timings().detection_s;
  const double t0 = omp_get_wtime();
  contact_.compute_normal(params_.contact, contact_input(), nodes_.f_con_x.data(), nodes_.f_con_y.data());
  const double wall = omp_get_wtime() - t0;
  // ContactTimings are read as cumulative seconds since the solver was made.
  const double detection = contact_.timings().detection_s - detection_before;
  timings_.contact_detection += detection;
  timings_.contact_forces += wall - detection;
  contact_work_step_ = contact_.stored_energy();
}

SplitPlan Model::check_freeze_bonds() {  // (4) freeze_bonds.cpp
  Stopwatch sw(timings_.bonds);
  return bonds_.check(*this);
}

// The step's topology changes, in one place: the bond points of the plan
// split (new nodes, masses, gather lists, stable step; bond_split.cpp). The
// checks before it only read the model.
void Model::apply_topology_changes(const SplitPlan& plan) {
  if (plan.empty()) return;
  Stopwatch sw(timings_.bonds);
  bonds_.split(*this, plan);
}

void Model::apply_cohesive_forces(History history) {  // (5) freeze_bonds.cpp
  Stopwatch sw(timings_.bonds);
  const bool commit = history == History::commit;
  bonds_.apply(*this, commit);
  if (!commit) return;
  // The ledger's cohesive term is the work done against the cohesive forces
  // (booked by update_positions); the part stored on the secant branches is
  // recoverable, so it moves from "dissipated" to "stored".
  const double stored = bonds_.stored();
  energy_.cohesive -= stored - energy_.cohesive_stored;
  energy_.cohesive_stored = stored;
}

void Model::assemble_forces() {
  // Per node, so shared by the threads (the other one would wait meanwhile:
  // ~10 arrays of the paper scene's 50,000 nodes).
  Stopwatch sw(timings_.integration);
  Nodes& N = nodes_;
  const int32_t n = N.size();
  const AssembleArrays a{N.f_x.data(),     N.f_y.data(),     N.f_con_x.data(), N.f_con_y.data(),
                         N.f_coh_x.data(), N.f_coh_y.data(), N.f_pre_x.data(), N.f_pre_y.data()};
  #pragma omp parallel for schedule(static) num_threads(int(partial_.size())) if (use_threads())
  for (int32_t i = 0; i < n; ++i) assemble_node(a, i);  // model/assemble_kernel.hpp
}

void Model::apply_friction(History history) {
  if (!contact_possible_) return;
  const double t0 = omp_get_wtime();
  const double detection_before = contact_.timings().detection_s;
  // The stick forces are the friction's history (the next step starts from
  // them): a look at the forces (evaluate) puts them back as they were.
  std::vector<uint64_t> keys;
  std::vector<double> stick;
  if (history == History::leave) {
    keys = contact_.warm_start_keys();
    stick = contact_.warm_start_forces();
  }
  const double power = contact_.apply_friction(params_.contact, contact_input(), nodes_.f_x.data(), nodes_.f_y.data());
  const double detection = contact_.timings().detection_s - detection_before;
  timings_.contact_detection += detection;
  const double forces = omp_get_wtime() - t0 - detection;
  timings_.contact_forces += forces;
  timings_.friction += forces;
  if (history == History::commit) {
    energy_.friction_solver += power * dt_;
  } else {
    contact_.set_warm_start(keys, stick);
  }
}

}  // namespace engine
