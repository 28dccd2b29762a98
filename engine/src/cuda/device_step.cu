// Whole steps on the GPU (cuda/device_step.hpp): the body forces, the normal
// contact, the bond check, the cohesive forces, the force assembly, friction,
// the boundary conditions and the update, in Model::advance's order, on one
// stream. Each stage is made with arrays of its own (the comparisons of
// docs/gpu.md make them from a model one at a time); the whole step then
// makes the arrays that one stage writes and another reads one array
// (share_arrays), so a step copies nothing on the GPU.
//
// The candidate list stays the one the model built until a node of a surface
// triangle has moved past its skin (the test of ContactSolver::list_still_valid,
// made on the GPU after each update). The next step's list is then searched
// on the GPU at the step's positions (cuda/broad_phase.cu: the CPU's search
// and layout), as the CPU's next step searches it, into the contact stages'
// arrays in place (rebuild_list): nothing else is made again, and the step
// is the GPU's. Any complete list gives the same touching
// pairs, so the same bits. Friction's warm start is kept per candidate
// (NaN: did not touch in the step before) and carried to the new list by key.
//
// Bond points split rarely (a few thousand in a paper run of a million
// steps), and a split changes the mesh: the GPU checks every step as
// FreezeBonds::check does (the same screening), and a step whose check finds
// a point at the criterion is the model's (the state goes back, the model
// splits, the stages are made again). A pair's full failure takes it out of
// the CPU's list of opened pairs; on the GPU it stays in the cohesive stage's
// list, passed over from then on (cohesive_forces.cu), and the steps go on:
// the stages are not made again for it.
//
// With a finite contact_reach the GPU tests every kReachCheckEvery steps, as
// Model::advance does, whether a node has moved past reach/2 since the
// contact step was bound; the model then re-bounds it after the step
// (Model::guard_contact_reach: masses raised, or the run stopped), and the
// stages are made again.
//
// Steps run in batches of up to kBatch: the host launches them one after
// the other and reads them back in one copy (each step's ledger sums,
// energies and flags in its StepRecord), then books each in order, as it
// would have one by one. A step that ends in an event the host must handle
// (the next step's check finds a point at eq 5, the list must be rebuilt, a
// node moved past reach/2, an element inverted, a sum not finite) sets the batch's halt word, and the batch's later kernels return
// at once (cuda/halt.cuh): the GPU's state is that step's, as if the batch
// had ended there. Only the energy alarm is the host's alone (it reads the
// booked ledger): a run it stops reports the ledger of the step that fired
// and the state of the batch's last step, up to kBatch - 1 steps later.
// A whole batch is one CUDA graph, captured on the stages and replayed until
// they are made again; what changes from step to step is read from GPU
// memory (the per-step arguments, written before each batch).
#include "cuda/device_step.hpp"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <string>
#include <utility>

#include "common/host_device.hpp"
#include "common/stopwatch.hpp"
#include "common/input_errors.hpp"
#include "contact/friction_kernel.hpp"
#include "cuda/body_forces_impl.cuh"
#include "cuda/broad_phase_impl.cuh"
#include "cuda/bond_check_impl.cuh"
#include "cuda/cohesive_forces_impl.cuh"
#include "cuda/contact_normal_impl.cuh"
#include "cuda/friction_impl.cuh"
#include "cuda/device_array.cuh"
#include "cuda/fixed_sums.cuh"
#include "cuda/node_update_impl.cuh"
#include "cuda/stream.cuh"
#include "cuda/halt.cuh"
#include "cuda/launch.cuh"
#include "loads/boundary_kernel.hpp"
#include "model/assemble_kernel.hpp"
#include "model/model.hpp"
#include "model/step_sums.hpp"

namespace engine {

namespace {

constexpr int kBlock = 128;

int blocks(int64_t n) { return int((n + kBlock - 1) / kBlock); }

// The step's one pass over the nodes between the pairs' kernels and
// friction's, each node's own values only: its opened pairs' forces and its
// crack closure (bonded), its total before friction (assemble_node), and
// friction's prediction from that total, where each of the four was a launch
// of its own (the stages' kernels, which their own launches still run).
__global__ void node_pass_kernel(const int32_t* halt, bool bonded, CohesiveNodeArrays c, AssembleArrays a,
                                 FrictionPredictArrays p, int32_t n) {  // p.mass null: no contact
  if (halted(halt)) return;
  const int32_t i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i >= n) return;
  if (bonded) {
    cohesive_node_sum(c, i);
    crack_closure_node(c, i);
  }
  assemble_node(a, i);
  if (p.mass) friction_predict(p, i);
}

// A new candidate list's warm start, per candidate (keys ascending): the
// tangential force of the old candidate with its key (old keys ascending),
// NaN where none (or where that one did not touch), as the model's merge.
__global__ void carry_warm_start_kernel(const uint64_t* key, int32_t n, const uint64_t* old_key, int64_t n_old,
                                        const double* old_lambda, double* lambda) {
  const int32_t c = blockIdx.x * blockDim.x + threadIdx.x;
  if (c >= n) return;
  const int64_t j = find_key(old_key, n_old, key[c]);
  lambda[c] = j >= 0 ? old_lambda[j] : NAN;
}

// The next step's warm start, per candidate: its tangential force if it
// touched, else NaN (absent, as a pair that did not touch is from the CPU's).
__global__ void warm_start_kernel(const int32_t* halt, const uint8_t* hit, const double* lambda, int32_t n,
                                  double* prev_lambda) {
  if (halted(halt)) return;
  const int32_t c = blockIdx.x * blockDim.x + threadIdx.x;
  if (c < n) prev_lambda[c] = hit[c] ? lambda[c] : NAN;
}

// NodeWork's terms in the update's sums (cuda/node_update.cu), by name.
enum Term { t_kinetic2_new, t_kinetic2_old, t_viscous, t_local_damping, t_contact, t_friction, t_cohesive,
            t_gravity, t_buoyancy, t_drag, t_boundary, t_elastic_new, t_elastic_old, n_terms };
// What a step copies back after the update's sums, by name.
enum Extra { x_elastic = n_terms, x_contact, x_friction_power, x_coh_work, x_coh_stored, x_coh_dissipation,
             n_copied };
// ... and its flags (f_split: the next step's check found a point at eq 5;
// f_nonfinite: a sum of the step is not finite).
enum Flag { f_inverted, f_moved, f_split, f_reach, f_nonfinite, n_flags };

// Steps of a batch, launched before one copy back. A batch costs the host a
// copy and a wait instead of one per step; a longer one runs further past an
// energy alarm (the header above) and captures a larger graph. 32 is a
// choice, not a measurement: no GPU has timed the batches yet.
constexpr int kBatch = 32;
// A whole batch turns the bond check's double buffer an even number of times,
// so a captured batch starts each replay from the buffer it was captured on.
static_assert(kBatch % 2 == 0, "kBatch must be even");

// What one step leaves for the host.
struct StepRecord {
  double sums[n_copied];
  int32_t flags[n_flags];
  unsigned long long evaluated;  // bond points the next step's check evaluated
};

// Where a step's scalars are on the GPU (nullptr: the model has none of it).
// A flag is set to none only where a step starts afresh (reset_flags): any
// other value is an event, which halts the batch, and every halt is followed
// by that.
struct StepScalars {
  const double* update;     // n_terms, the update's sums
  const double* elastic;    // the strain energy
  const int32_t* inverted;  // the first inverted element, 0x7f7f7f7f if none
  const double* contact;    // the contact energy
  const double* power;      // the friction power
  const int32_t* moved;     // a node past the skin
  const int32_t* reach;     // a node past reach/2 (0 in the steps that do not test it)
  const double* cohesive;   // work, stored, effective dissipation
};

__device__ inline bool finite_sum(double v) { return fabs(v) <= DBL_MAX; }  // false for NaN too

// An event of the step itself (its record's flags) that the host handles
// after it: the record kernel halts the batch on it, the host finds it.
ICERUBBLE_HD bool step_event(const int32_t* f) {
  return f[f_inverted] != 0x7f7f7f7f || f[f_moved] || f[f_reach] || f[f_nonfinite];
}

// The step's sums and flags into its record (one lane); an event halts the
// batch. Every value is read before any is written: the compiler cannot know
// that the record aliases none of them, so each load waited for the store
// before it, ~20 trips to memory one after another (5.8 us a step on an H200).
__global__ void record_step_kernel(int32_t* halt, StepScalars s, StepRecord* r) {
  if (halted(halt)) return;
  double t[n_copied];
  for (int k = 0; k < n_terms; ++k) t[k] = s.update[k];
  t[x_elastic] = *s.elastic;
  t[x_contact] = s.contact ? *s.contact : 0.0;
  t[x_friction_power] = s.power ? *s.power : 0.0;
  for (int k = 0; k < 3; ++k) t[x_coh_work + k] = s.cohesive ? s.cohesive[k] : 0.0;
  int32_t f[n_flags];
  f[f_inverted] = *s.inverted;
  f[f_moved] = s.moved ? *s.moved : 0;
  f[f_reach] = s.reach ? *s.reach : 0;
  bool finite = true;
  for (int k = 0; k < n_copied; ++k) finite = finite && finite_sum(t[k]);
  f[f_nonfinite] = finite ? 0 : 1;
  f[f_split] = 0;
  for (int k = 0; k < n_copied; ++k) r->sums[k] = t[k];
  for (int k = 0; k < n_flags; ++k) r->flags[k] = f[k];
  r->evaluated = 0;
  if (step_event(f)) *halt = 1;
}

// The next step's check into the step's record (nullptr: no check), its
// count of points evaluated set to zero again for the check after; a point
// at eq 5 halts the batch (its flag is set to none again by reset_flags).
__global__ void record_check_kernel(int32_t* halt, int32_t* split, unsigned long long* evaluated, StepRecord* r) {
  if (halted(halt)) return;
  r->flags[f_split] = split ? *split : 0;
  r->evaluated = evaluated ? *evaluated : 0;
  if (evaluated) *evaluated = 0;
  if (r->flags[f_split]) *halt = 1;
}

}  // namespace

struct DeviceStep::Impl {
  Model* model = nullptr;  // the one it was made from: it takes the steps the GPU does not
  bool contact = false;    // the model has two bodies or more
  std::unique_ptr<DeviceBodyForces> forces;
  std::unique_ptr<DeviceNodeUpdate> update;
  std::unique_ptr<DeviceContactNormal> normal;
  std::unique_ptr<DeviceFriction> friction;
  std::unique_ptr<DeviceBondCheck> check;         // bonded models: the check (when checking)
  std::unique_ptr<DeviceCohesiveForces> cohesive;  // ... and the cohesive forces
  std::unique_ptr<DeviceBroadPhase> broad;        // contact: the candidate list searched on the GPU
  bool bonded = false;    // the model has bond points
  bool checking = false;  // ... and checks them (BondParams::check_failure)
  // the bonds' accounts (FreezeBonds: work, stored, effective dissipation,
  // points evaluated), the model's when the stages were made, then the GPU's steps'
  double bond_work = 0.0, bond_stored = 0.0, bond_dissipation = 0.0;
  int64_t bond_checks = 0;
  std::vector<BoundaryCondition> bcs;
  // the conditions' value column of each node's x and y component (-1: free)
  DeviceArray<int32_t> bc_col_x, bc_col_y;
  bool prescribed = false;  // any component prescribed
  // the candidate list's test (UpdateTests): the nodes of surface triangles, a node moved past the skin
  DeviceArray<uint8_t> on_surface;
  DeviceArray<int32_t> moved;
  DeviceArray<double> list_x, list_y;
  // the contact reach guard (finite contact_reach): where each node's move
  // is measured from, half the reach, a node moved past it
  bool reach_guard = false;
  double reach_half = 0.0;
  DeviceArray<double> reach_x, reach_y;
  DeviceArray<int32_t> reach_moved;
  double skin = 0.0;
  bool list_valid = true;
  // the next step's prologue has run; it checked bonds, found a point at
  // eq 5, evaluated this many points
  bool primed = false, primed_check = false, next_split = false;
  unsigned long long next_evaluated = 0;
  double dt = 0.0, time = 0.0;
  int64_t step_count = 0, host_steps = 0;
  // wall time [s]: the host steps (state to the model, its step, its next
  // list after a split) and the stages made from the model (copies included)
  double host_step_seconds = 0.0, make_seconds = 0.0;
  int64_t remakes = 0;  // the stages made again from the model (after a host step or a re-bound)
  // the candidate list rebuilt in place (rebuild_list), and its wall time [s]
  int64_t list_rebuilds = 0;
  double list_seconds = 0.0;
  EnergyLedger energy;
  cudaStream_t stream = nullptr;  // the body-force stage's; every stage runs on it
  // a batch's records (kBatch, then prime's) and where they are read; its halt word
  DeviceArray<StepRecord> records;
  StepRecord* host_records = nullptr;  // pinned, kBatch + 1
  DeviceArray<int32_t> halt_word;
  int32_t* halt = nullptr;  // halt_word's
  // A batch's per-step arguments in GPU memory, so that a batch captured
  // once replays with the next batch's: per row (a step of the batch; row
  // kBatch, prime's), its start time and the boundary conditions' values at
  // its midpoint (values, `width` per row), whether it tests the reach and
  // the step number of the next step's check (counts, 2 per row).
  int width = 1;  // 1 + the boundary components launched
  DeviceArray<double> values;
  DeviceArray<int64_t> counts;
  double* host_values = nullptr;  // pinned, as values
  int64_t* host_counts = nullptr;  // pinned, as counts
  // a whole batch's launches captured on these stages (a CUDA graph), the
  // check's flags array it reads first; stale: the stages' arrays or sizes
  // changed since (a list rebuild, a remake), captured again before a replay
  cudaGraphExec_t batch_graph = nullptr;
  const int8_t* graph_near = nullptr;
  bool graph_stale = false;
  // captures put into the executable graph in place, and instantiated afresh
  int64_t graph_updates = 0, graph_instantiations = 0;
  // friction's colourings made by the stages released so far (their own count goes with them)
  int64_t colourings_before = 0;
  int64_t colourings() const {
    return colourings_before + (friction ? int64_t(friction->impl_->counts.download()[c_colourings]) : 0);
  }

  DeviceBodyForces::Impl& f() { return *forces->impl_; }
  DeviceNodeUpdate::Impl& u() { return *update->impl_; }
  DeviceContactNormal::Impl& cn() { return *normal->impl_; }
  DeviceFriction::Impl& fr() { return *friction->impl_; }
  DeviceBondCheck::Impl& bc() { return *check->impl_; }
  DeviceCohesiveForces::Impl& co() { return *cohesive->impl_; }
  DeviceBroadPhase::Impl& bp() { return *broad->impl_; }

  template <class T>
  void fetch(T* host, const DeviceArray<T>& from, size_t first, size_t n) {
    cuda_check(cudaMemcpyAsync(host, from.data() + first, n * sizeof(T), cudaMemcpyDeviceToHost, stream),
               "copy from GPU");
  }
  template <class T>
  void zero(DeviceArray<T>& a) {
    cuda_check(cudaMemsetAsync(a.data(), 0, a.size() * sizeof(T), stream), "memset");
  }

  // Every stage runs on the body-force stage's stream, destroyed with it:
  // the others forget theirs before they go.
  void release_stages() {
    mark_graph_stale();
    if (update) u().stream = nullptr;
    if (normal) cn().stream = nullptr;
    if (friction) fr().stream = nullptr;
    if (check) bc().stream = nullptr;
    if (cohesive) co().stream = nullptr;
    if (broad) bp().stream = nullptr;
    broad.reset();
    update.reset();
    normal.reset();
    friction.reset();
    check.reset();
    cohesive.reset();
    forces.reset();
  }
  // The batch's graph is captured again before its next replay; the
  // executable graph is kept for that capture to update in place.
  void mark_graph_stale() { graph_stale = true; }
  void destroy_graph() {
    if (batch_graph) cudaGraphExecDestroy(batch_graph);
    batch_graph = nullptr;
    graph_stale = false;
  }
  // The batch's buffers: the halt word and the records once, the per-step
  // arguments' arrays for the boundary conditions made now.
  void size_batch_buffers() {
    if (!halt) {
      halt_word.resize(1);
      halt = halt_word.data();
      records.resize(kBatch + 1);
      cuda_check(cudaMallocHost(&host_records, (kBatch + 1) * sizeof(StepRecord)), "cudaMallocHost");
    }
    int w = 1;
    for (const BoundaryCondition& bc : bcs) w += int(bc.x) + int(bc.y);
    if (w == width && host_values) return;
    width = w;
    values.resize(size_t(kBatch + 1) * size_t(width));
    counts.resize(2 * size_t(kBatch + 1));
    if (host_values) cudaFreeHost(host_values);
    host_values = nullptr;
    cuda_check(cudaMallocHost(&host_values, values.size() * sizeof(double)), "cudaMallocHost");
    if (!host_counts) cuda_check(cudaMallocHost(&host_counts, counts.size() * sizeof(int64_t)), "cudaMallocHost");
  }
  const double* time_at(int row) const { return values.data() + size_t(row) * width; }
  const double* boundary_at(int row, int j) const { return values.data() + size_t(row) * width + 1 + j; }
  const int64_t* reach_now_at(int row) const { return counts.data() + 2 * size_t(row); }
  const int64_t* check_step_at(int row) const { return counts.data() + 2 * size_t(row) + 1; }

  // A stage made with a stream of its own moves onto the step's.
  void adopt(cudaStream_t& s) {
    cuda_check(cudaStreamDestroy(s), "cudaStreamDestroy");
    s = stream;
  }

  // The stages made from the model as it is now, with its candidate list
  // (after a step of its own: the one that step built), on one stream.
  void make_stages() {
    Stopwatch sw(make_seconds);
    const Model& cm = *model;
    ++remakes;
    colourings_before = colourings();  // (not in release_stages: the destructor's must not throw)
    release_stages();
    // the boundary conditions: a node split off a held or driven node is held or driven too
    bcs = cm.boundary_conditions();
    list_boundary_entries();
    forces.reset(new DeviceBodyForces(cm));
    size_batch_buffers();  // after a stage, which says so when no GPU is visible
    update.reset(new DeviceNodeUpdate(cm));
    stream = f().stream;
    adopt(u().stream);
    for (DeviceArray<double>* a : {&u().f_con_x, &u().f_con_y})  // no contact: zero for good
      cuda_check(cudaMemsetAsync(a->data(), 0, a->size() * sizeof(double), stream), "memset");
    list_valid = true;
    primed = false;
    if (!contact) {
      share_arrays();
      give_halt();
      return settle_uploads();
    }
    normal.reset(new DeviceContactNormal(cm));
    // the model's warm start (keys of the pairs of its last step) per candidate
    friction.reset(new DeviceFriction(cm, DeviceFriction::WarmStart::per_candidate));
    broad.reset(new DeviceBroadPhase(cm));
    adopt(cn().stream);
    adopt(fr().stream);
    adopt(bp().stream);
    if (bonded) {
      const FreezeBonds& B = cm.bonds();
      if (checking) {
        check.reset(new DeviceBondCheck(cm));
        adopt(bc().stream);
      }
      cohesive.reset(new DeviceCohesiveForces(cm));
      adopt(co().stream);
      bond_work = B.work();
      bond_stored = B.stored();
      bond_dissipation = B.dissipation_effective();
      bond_checks = B.checks();
    }
    // the list's test: the nodes of the surface triangles, where the list was built, its skin
    std::vector<uint8_t> on(size_t(cm.nodes().size()), 0);
    for (const int32_t t : cm.surface_triangles())
      for (int k = 0; k < 3; ++k) on[size_t(cm.triangles().node[3 * size_t(t) + k])] = 1;
    on_surface.upload(on);
    list_x.upload(cm.contact().list_origin_x());
    list_y.upload(cm.contact().list_origin_y());
    skin = cm.contact().list_skin();
    moved.resize(1);
    if (reach_guard) {  // the model's origins, a node split off since at its reference place
      model->extend_reach_origin();
      reach_x.upload(cm.reach_origin_x());
      reach_y.upload(cm.reach_origin_y());
      reach_moved.resize(1);
    }
    share_arrays();
    give_halt();
    settle_uploads();
  }

  // The update's boundary columns (UpdateBoundary): per condition, its x
  // then y component, value column j as run_batch writes them; a (node,
  // component) set again by a later condition keeps the last, as the CPU's
  // loop over the conditions leaves it.
  void list_boundary_entries() {
    const size_t n = size_t(static_cast<const Model&>(*model).nodes().size());
    std::vector<int32_t> col_x(n, -1), col_y(n, -1);
    int32_t j = 0;
    for (const BoundaryCondition& bc : bcs)
      for (int c = 0; c < 2; ++c) {
        if (!(c ? bc.y : bc.x)) continue;
        for (const int32_t i : bc.nodes) (c ? col_y : col_x)[size_t(i)] = j;
        ++j;
      }
    prescribed = j > 0;
    bc_col_x.upload(col_x);
    bc_col_y.upload(col_y);
  }

  // Every stage's kernels return once the batch's halt word is set.
  void give_halt() {
    forces->impl_->halt = halt;
    u().halt = halt;
    if (normal) cn().halt = halt;
    if (friction) fr().halt = halt;
    if (check) bc().halt = halt;
    if (cohesive) co().halt = halt;
  }

  // One array for each quantity a stage writes and another reads, in the
  // step's order (launch_step): the node state is the update's; the body-force
  // stage's outputs are what the update books and what the force assembly
  // starts from; friction reads the assembly's total and writes the step's
  // total over the body forces (read before it by the cohesive pairs and the
  // assembly); the contact forces are the normal pass's (it writes every
  // node), the crack closure added in place after the cohesive pairs have
  // read them.
  void share_arrays() {
    DeviceBodyForces::Impl& F = f();
    DeviceNodeUpdate::Impl& U = u();
    F.reset_inverted = false;  // reset_flags
    F.sum_energy = false;      // the step's sums (launch_step)
    F.x.alias(U.x);
    F.y.alias(U.y);
    F.vx.alias(U.vx);
    F.vy.alias(U.vy);
    U.f_int_x.alias(F.f_int_x);
    U.f_int_y.alias(F.f_int_y);
    U.f_visc_x.alias(F.f_visc_x);
    U.f_visc_y.alias(F.f_visc_y);
    U.f_buoy_y.alias(F.f_buoy_y);
    U.drag_k.alias(F.drag_k);
    U.f_x.alias(F.f_x);
    U.f_y.alias(F.f_y);
    U.f_coh_x.alias(bonded ? co().f_coh_x : F.f_coh_x);
    U.f_coh_y.alias(bonded ? co().f_coh_y : F.f_coh_y);
    if (!contact) return;  // the contact forces stay zero (make_stages)
    DeviceContactNormal::Impl& N = cn();
    DeviceFriction::Impl& R = fr();
    N.pair_sums = false;  // the step's sums (launch_step)
    N.x.alias(U.x);
    N.y.alias(U.y);
    U.f_con_x.alias(N.f_con_x);
    U.f_con_y.alias(N.f_con_y);
    R.x.alias(U.x);
    R.y.alias(U.y);
    R.vx.alias(U.vx);
    R.vy.alias(U.vy);
    R.f_pre_x.alias(U.f_pre_x);
    R.f_pre_y.alias(U.f_pre_y);
    R.f_x.alias(F.f_x);
    R.f_y.alias(F.f_y);
    // friction's pair results are the normal pass's: both stages lay out the
    // model's candidates alike (contact/candidate_layout.hpp) and evaluate
    // them at the step's positions with the same penalty, so one pass of the
    // pair kernel serves both
    if (N.n_pairs != R.n_cand || N.penalty != R.penalty)
      throw std::logic_error("GPU step: the normal pass and friction were made from different candidates");
    R.hit.alias(N.hit);
    R.node.alias(N.node);  // one layout (contact/candidate_layout.hpp)
    R.start.alias(N.start);
    R.entry.alias(N.entry);
    N.friction_pairs = {R.nc.data(), R.nt.data(), R.nx.data(), R.ny.data(), R.fn.data()};
    R.pairs_given = true;
    R.predicted = true;  // node_pass_kernel
    R.totals_given = true;  // node_pass_kernel's assemble_node: f_x = f_pre
  }

  // The uploads (cudaMemcpy, on the legacy stream) done before the first
  // launch on the step's non-blocking stream, which does not wait for them:
  // a copy from pageable memory may return before its transfer has ended.
  static void settle_uploads() { cuda_check(cudaDeviceSynchronize(), "GPU uploads"); }

  // The flags a step's kernels set (an element inverted, the check's split
  // and count, a node past the skin or reach/2) to none, where a step starts
  // afresh: after the stages are made, or after a halt (prime). A flag set
  // halts the batch, so between halts they stay none, but for the count,
  // which record_check_kernel sets to zero once read: a launch a step fewer
  // for each.
  void reset_flags() {
    cuda_check(cudaMemsetAsync(f().inverted.data(), 0x7f, sizeof(int32_t), stream), "memset");
    if (checking && bc().n_intact > 0) {
      zero(bc().split);
      zero(bc().evaluated);
    }
    if (contact) zero(moved);
    if (reach_guard) zero(reach_moved);
  }

  // A step's first part, which reads only the state at its start: (1) the
  // elements and (6) the water loads and gravity, gathered onto the nodes,
  // and (4) the bond check of the step number in argument row `row`, its
  // result into `r`. It
  // runs at the end of the step before (after the update, in the same
  // batch), so that a step whose check splits a point is known before
  // anything of it is committed; after the stages are made again, it runs on
  // its own (prime).
  void prologue(int row, StepRecord* r) {
    DeviceBodyForces::Impl& F = f();
    F.launch();
    primed_check = checking && bc().n_intact > 0;
    if (!primed_check) return launch_kernel(record_check_kernel, 1, 1, stream, halt, nullptr, nullptr, r);
    DeviceBondCheck::Impl& K = bc();  // its flag and count zero (record_check_kernel, reset_flags)
    K.launch_screened(F.x.data(), F.y.data(), F.stress.data(), check_step_at(row));
    launch_kernel(record_check_kernel, 1, 1, stream, halt, K.split.data(), K.evaluated.data(), r);
  }
  void prime() {
    host_counts[2 * kBatch + 1] = step_count;
    cuda_check(cudaMemcpyAsync(counts.data() + 2 * kBatch + 1, host_counts + 2 * kBatch + 1, sizeof(int64_t),
                               cudaMemcpyHostToDevice, stream),
               "copy to GPU");
    zero(halt_word);
    reset_flags();
    prologue(kBatch, records.data() + kBatch);
    fetch(host_records + kBatch, records, kBatch, 1);
    cuda_check(cudaStreamSynchronize(stream), "GPU step");
    primed = true;
    next_split = host_records[kBatch].flags[f_split] != 0;
    next_evaluated = host_records[kBatch].evaluated;
  }

  // n steps: the model's where the list must be rebuilt or the next step's
  // check found a point at eq 5, the GPU's in batches otherwise.
  void advance(int64_t n) {
    const int64_t end = step_count + n;
    while (step_count < end) {
      if (!list_valid) {
        rebuild_list();
        continue;
      }
      if (!primed) prime();
      // the step's check (its prologue) found a point at eq 5: the step is the
      // model's, from the state at its start, which nothing has changed yet
      if (primed_check && next_split) {
        host_step();
        continue;
      }
      run_batch(int(std::min<int64_t>(end - step_count, kBatch)));
    }
  }

  // k steps launched, read back in one copy and booked in order, up to the
  // first that ended in an event (the GPU halted after it), which is then
  // handled as a step on its own was. A whole batch is launched as a CUDA
  // graph, captured once on these stages and replayed with each batch's
  // arguments.
  void run_batch(int k) {
    const bool checked = primed_check;  // alike in every step of the batch: n_intact changes with the stages only
    double t = time;  // each step's start, as book() advances it
    for (int s = 0; s < k; ++s) {
      double* v = host_values + size_t(s) * width;
      v[0] = t;
      const double t_half = t + 0.5 * dt;  // the boundary conditions at the step's midpoint
      int j = 1;
      for (const BoundaryCondition& bc : bcs) {
        const double h = bc.history.at(t_half);
        if (bc.x) v[j++] = bc.dir_x * h;
        if (bc.y) v[j++] = bc.dir_y * h;
      }
      const int64_t step = step_count + s;
      host_counts[2 * s] = reach_guard && (step + 1) % Model::kReachCheckEvery == 0;  // the step number after this one
      host_counts[2 * s + 1] = step + 1;  // the next step's check
      t += dt;
    }
    cuda_check(cudaMemcpyAsync(values.data(), host_values, size_t(k) * width * sizeof(double), cudaMemcpyHostToDevice,
                               stream),
               "copy to GPU");
    cuda_check(cudaMemcpyAsync(counts.data(), host_counts, 2 * size_t(k) * sizeof(int64_t), cudaMemcpyHostToDevice,
                               stream),
               "copy to GPU");
    if (k < kBatch) {
      launch_batch(k, checked);
    } else {
      if (!batch_graph || graph_stale || (checked && bc().near.data() != graph_near)) capture_batch(checked);
      cuda_check(cudaGraphLaunch(batch_graph, stream), "graph launch");
    }
    fetch(host_records, records, 0, size_t(k));
    cuda_check(cudaStreamSynchronize(stream), "GPU step");
    int last = k - 1;
    for (int s = 0; s < k; ++s)
      if (step_event(host_records[s].flags) || host_records[s].flags[f_split]) {
        last = s;
        break;
      }
    // the halted steps' turns of the double buffer taken back
    if (checked && (k - 1 - last) % 2) bc().near.swap(bc().near_next);
    for (int s = 0; s <= last; ++s) {
      if (checked) bond_checks += int64_t(next_evaluated);  // the step's check, run before it
      next_evaluated = host_records[s].evaluated;
      book(host_records[s]);
    }
    const StepRecord& r = host_records[last];
    // after an event of the step itself the GPU halted before the next step's
    // first part: it runs again on the stages as they will be
    primed = !step_event(r.flags);
    next_split = r.flags[f_split] != 0;
    // a node moved past reach/2: the model re-bounds the contact step
    if (r.flags[f_reach]) {
      to_model();
      model->guard_contact_reach();
      energy = model->energy();  // a raise books the kinetic energy it takes as damping
      // this step's reactions (the new stages start from the model's, of its own last step)
      const std::vector<double> r_x = u().r_x.download(), r_y = u().r_y.download();
      make_stages();
      u().r_x.upload(r_x);
      u().r_y.upload(r_y);
      settle_uploads();
    }
    list_valid = r.flags[f_moved] == 0;
  }
  // The launches of a batch of k steps.
  void launch_batch(int k, bool checked) {
    zero(halt_word);
    for (int s = 0; s < k; ++s) {
      launch_step(s, records.data() + s);
      if (checked) bc().near.swap(bc().near_next);  // the step's flags are the points' now
      prologue(s, records.data() + s);  // the next step's first part
    }
  }
  // A whole batch's launches captured (not run) into batch_graph: put into
  // the executable graph in place where it has the same launches (a list
  // rebuild or a remake changes arrays and sizes, seldom the launches;
  // ~2,800 of them in a 300 mm paper run), instantiated afresh otherwise.
  void capture_batch(bool checked) {
    const int8_t* near = checked ? bc().near.data() : nullptr;
    cudaGraph_t g;
    cuda_check(cudaStreamBeginCapture(stream, cudaStreamCaptureModeThreadLocal), "graph capture");
    launch_batch(kBatch, checked);  // turns the double buffer kBatch times: back where it was
    cuda_check(cudaStreamEndCapture(stream, &g), "graph capture");
    bool updated = false;
    if (batch_graph) {
      cudaGraphExecUpdateResultInfo info;
      updated = cudaGraphExecUpdate(batch_graph, g, &info) == cudaSuccess;
      if (!updated) {
        cudaGetLastError();  // the refusal, not a fault: instantiated afresh below
        destroy_graph();
      }
    }
    if (updated) {
      ++graph_updates;
    } else {
      cuda_check(cudaGraphInstantiate(&batch_graph, g, 0), "graph instantiate");
      ++graph_instantiations;
    }
    cudaGraphDestroy(g);
    graph_near = near;
    graph_stale = false;
  }

  // A step's launches after its prologue, with the arguments of row `row`,
  // its sums and flags into r.
  void launch_step(int row, StepRecord* r) {
    DeviceBodyForces::Impl& F = f();
    DeviceNodeUpdate::Impl& U = u();
    const int32_t n = U.n;
    if (contact) cn().launch();  // (3) normal contact over the candidates
    // (5) the opened pairs' cohesive forces, history and failures; each
    // node's sums of them and its crack closure in the node pass below
    CohesiveNodeArrays cohesive_nodes{};
    if (bonded) {
      DeviceCohesiveForces::Impl& C = co();
      const CohesivePairArrays a = C.arrays(F.x.data(), F.y.data(), F.vx.data(), F.vy.data(), F.f_x.data(),
                                            F.f_y.data(), cn().f_con_x.data(), cn().f_con_y.data());
      C.launch_committed(a, time_at(row), U.f_con_x.data(), U.f_con_y.data(), false, false);
      cohesive_nodes = C.node_arrays(a, U.f_con_x.data(), U.f_con_y.data());
    }
    // (the body forces, the contact forces with the crack closure and the
    // cohesive forces are the update's arrays already: share_arrays)
    // the node pass: the cohesive sums and crack closure, the total before
    // friction, friction's prediction from it
    const AssembleArrays a{U.f_x.data(),     U.f_y.data(),     U.f_con_x.data(), U.f_con_y.data(),
                           U.f_coh_x.data(), U.f_coh_y.data(), U.f_pre_x.data(), U.f_pre_y.data()};
    FrictionPredictArrays p{};
    if (contact) p = fr().predict_arrays();
    launch_kernel(node_pass_kernel, blocks(n), kBlock, stream, halt, bonded, cohesive_nodes, a, p, n);
    if (contact) {  // (3b) friction, from the total before it
      DeviceFriction::Impl& R = fr();
      R.launch();  // the step's total into U.f_x, U.f_y (share_arrays)
      if (R.n_cand)
        launch_kernel(warm_start_kernel, blocks(R.n_cand), kBlock, stream, halt, R.hit.data(), R.lambda.data(),
                      R.n_cand, R.prev_lambda.data());
    }
    // the boundary conditions at the step's midpoint, as Model::apply_boundary_conditions,
    // applied to each node in the update's launch right before its update
    UpdateBoundary boundary;
    if (prescribed) {
      boundary.x = bc_col_x.data();
      boundary.y = bc_col_y.data();
      boundary.values = boundary_at(row, 0);
      boundary.inv_dt = dt > 0.0 ? 1.0 / dt : 0.0;
      boundary.cx = BoundaryComponent{U.mass.data(), U.vx.data(), U.f_x.data(), U.v_bc_x.data(), U.r_x.data()};
      boundary.cy = BoundaryComponent{U.mass.data(), U.vy.data(), U.f_y.data(), U.v_bc_y.data(), U.r_y.data()};
    }
    // (7) the central difference and the ledger's sums, each updated node
    // tested against the list's skin and, in the steps the row says, the reach
    StepScalars sc{U.sums.data(), F.total.data(), F.inverted.data(), nullptr, nullptr, nullptr, nullptr, nullptr};
    UpdateTests tests;
    if (contact) {
      tests.on_surface = on_surface.data();
      tests.list_x = list_x.data();
      tests.list_y = list_y.data();
      tests.skin = skin;
      tests.moved = moved.data();
      sc.contact = cn().total.data();
      sc.power = fr().power.data();
      sc.moved = moved.data();
      if (reach_guard) {
        tests.reach_now = reach_now_at(row);
        tests.reach_x = reach_x.data();
        tests.reach_y = reach_y.data();
        tests.reach_half = reach_half;
        tests.reach_moved = reach_moved.data();
        sc.reach = reach_moved.data();
      }
    }
    U.launch(tests, boundary, false);
    // the step's sums in one launch, a block each: the update's terms, the
    // cohesive pairs' terms, the contact energy and the strain energy (of
    // the triangles' pass in this step's prologue), each the stage's own
    // additions (sum_jobs_kernel)
    SumJobs jobs;
    for (size_t k = 0; k < U.sums.size(); ++k)
      jobs.add(U.partial.data() + k * size_t(U.n_blocks()), U.n_blocks(), U.sums.data() + k);
    if (bonded) {
      DeviceCohesiveForces::Impl& C = co();
      for (size_t k = 0; k < C.sums.size(); ++k)
        jobs.add(C.partial.data() + k * size_t(C.n_blocks()), C.n_blocks(), C.sums.data() + k);
      sc.cohesive = C.sums.data();
    }
    if (contact) jobs.add(cn().pair_energy.data(), cn().n_pairs, cn().total.data());
    jobs.add(F.partial.data(), int64_t(F.partial.size()), F.total.data());
    launch_kernel(sum_jobs_kernel<kWideBlock>, jobs.n, kWideBlock, stream, halt, jobs);
    launch_kernel(record_step_kernel, 1, 1, stream, halt, sc, r);
  }

  // The candidate list rebuilt where the step's positions are, on the GPU
  // (DeviceBroadPhase: the CPU's search and layout, cuda/broad_phase.cu), as
  // the CPU's next step builds it at the same state, into the contact
  // stages' arrays; friction's warm start carried to the new list by key;
  // the list's test from here. The positions never leave the GPU: one wait
  // for the candidates' count. The model is not touched (download() gives it
  // the GPU's state; its own list stays complete by its own test). The
  // batch's graph is captured again: the candidates' arrays and count are
  // its arguments.
  void rebuild_list() {
    {
      Stopwatch sw(list_seconds);
      DeviceContactNormal::Impl& N = cn();
      DeviceFriction::Impl& R = fr();
      DeviceNodeUpdate::Impl& U = u();
      DeviceArray<uint64_t> old_key;  // the warm start's, kept until carried over
      old_key.swap(R.prev_key);
      const int64_t n_old = R.n_prev;
      const int32_t m = bp().search(U.x.data(), U.y.data(), LayoutArrays{&N.node, &R.key, &N.start, &N.entry}, skin);
      N.size_pairs(size_t(m));
      R.size_pairs(size_t(m));
      R.forget_colouring();
      DeviceArray<double> lambda(static_cast<size_t>(m));
      if (m) launch_kernel(carry_warm_start_kernel, blocks(m), kBlock, stream, R.key.data(), m, old_key.data(), n_old,
                           R.prev_lambda.data(), lambda.data());
      R.prev_lambda.swap(lambda);
      R.prev_key.resize(size_t(m));
      if (m) cuda_check(cudaMemcpyAsync(R.prev_key.data(), R.key.data(), size_t(m) * sizeof(uint64_t),
                                        cudaMemcpyDeviceToDevice, stream), "copy on GPU");
      R.n_prev = m;
      const size_t nn = size_t(U.n);
      cuda_check(cudaMemcpyAsync(list_x.data(), U.x.data(), nn * sizeof(double), cudaMemcpyDeviceToDevice, stream),
                 "copy on GPU");
      cuda_check(cudaMemcpyAsync(list_y.data(), U.y.data(), nn * sizeof(double), cudaMemcpyDeviceToDevice, stream),
                 "copy on GPU");
      share_arrays();  // friction's layout and pair arrays are the normal pass's again
      mark_graph_stale();
      cuda_check(cudaStreamSynchronize(stream), "GPU list rebuild");  // before the old arrays go
    }
    ++list_rebuilds;
    list_valid = true;
  }

  // The model takes the step (a step whose check splits points), and the
  // stages are made again from it. A step that split points searched for
  // neighbours before it split (Model::compute_forces' order), so the list it
  // leaves is of the mesh before: the model's next step searches again, on
  // the split mesh, and build_contact_list builds that list now, at the same
  // state, for the stages to start from (the broad phase alone: a whole
  // evaluation here cost the paper mesh a force pass per split step).
  void host_step() {
    {
      Stopwatch sw(host_step_seconds);
      to_model();
      const Model& cm = *model;
      const int32_t nodes_before = cm.nodes().size();
      model->step(1);
      if (contact && cm.nodes().size() != nodes_before) model->build_contact_list();
    }
    ++host_steps;
    time = model->time();
    step_count = model->step_count();
    energy = model->energy();
    make_stages();
  }

  // The ledger as Model::update_positions books it (the CPU's sums of
  // gravity and drag are the negated sums of NodeWork's terms), with the
  // contact module's accounts as Model::compute_forces keeps them.
  void book(const StepRecord& r) {
    const double* t = r.sums;
    if (bonded) {  // FreezeBonds::apply's accounts and Model::apply_cohesive_forces' booking
      const double stored = t[x_coh_stored];
      bond_work += t[x_coh_work];
      bond_stored = stored;
      bond_dissipation += t[x_coh_dissipation];
      energy.cohesive -= stored - energy.cohesive_stored;
      energy.cohesive_stored = stored;
    }
    StepSums s;
    s.kinetic2_new = t[t_kinetic2_new];
    s.kinetic2_old = t[t_kinetic2_old];
    s.viscous = t[t_viscous];
    s.local_damping = t[t_local_damping];
    s.contact = t[t_contact];
    s.friction = t[t_friction];
    s.cohesive = t[t_cohesive];
    s.gravity = -t[t_gravity];
    s.buoyancy = t[t_buoyancy];
    s.drag = -t[t_drag];
    s.boundary = t[t_boundary];
    s.elastic_new = t[t_elastic_new];
    s.elastic_old = t[t_elastic_old];
    energy.elastic = t[x_elastic];
    energy.friction_solver += t[x_friction_power] * dt;
    energy.book_step(s, dt, t[x_contact]);
    time += dt;
    ++step_count;
    const int32_t inverted = r.flags[f_inverted] == 0x7f7f7f7f ? -1 : r.flags[f_inverted];
    const std::string at = "GPU step: run stopped at step " + std::to_string(step_count) + " (t = " + num(time) + " s): ";
    if (!std::isfinite(energy.kinetic) || !std::isfinite(energy.elastic))
      throw InstabilityError(at + "non-finite " + (std::isfinite(energy.kinetic) ? "elastic" : "kinetic") +
                             " energy; run the model on the CPU from the last state to find where");
    if (inverted >= 0)
      throw InstabilityError(at + "element " + std::to_string(inverted) +
                             " inverted (det F <= 0): the mesh has collapsed, usually a too large dt");
    // energy growing without a source: the model's own check on the ledger
    // booked here; the model then says where (and stops the run)
    const Model& cm = *model;
    if (cm.parameters().check_energy && cm.energy_alarm(energy).fires()) {
      to_model();
      model->guard_stability();
    }
  }

  // The state into the model: positions, velocities, clock, ledger, the
  // friction warm start (the candidates that touched in the last step) and
  // the bonds' state.
  void to_model() {
    cuda_check(cudaStreamSynchronize(stream), "GPU step");
    Model& m = *model;
    m.set_positions(u().x.download(), u().y.download());
    m.set_velocities(u().vx.download(), u().vy.download());
    m.restore_energy(energy);
    m.restore_clock(time, step_count);
    if (!contact) return;
    const std::vector<uint64_t> keys = fr().prev_key.download();
    const std::vector<double> prev = fr().prev_lambda.download();
    std::vector<uint64_t> wk;
    std::vector<double> wl;
    for (size_t c = 0; c < keys.size(); ++c)
      if (!std::isnan(prev[c])) {
        wk.push_back(keys[c]);
        wl.push_back(prev[c]);
      }
    m.set_contact_warm_start(wk, wl);
    if (bonded) bonds_to_model(m);
  }

  // The opened pairs' history, their failures, the screening flags and the
  // accounts into the model's bonds (the rest of their state changes only
  // in the model's own steps).
  void bonds_to_model(Model& m) {
    BondState s = static_cast<const Model&>(m).bonds().state();
    DeviceCohesiveForces::Impl& C = co();
    s.delta_m = C.delta_m_in.download();
    s.f_n_prev = C.f_n_prev.download();
    s.f_t_prev = C.f_t_prev.download();
    s.d_n_prev = C.d_n_prev.download();
    s.d_t_prev = C.d_t_prev.download();
    s.t_fail = C.t_fail.download();
    s.x_fail = C.x_fail.download();
    s.y_fail = C.y_fail.download();
    s.dn_fail = C.dn_fail.download();
    s.dt_fail = C.dt_fail.download();
    s.pair_state = C.pair_state.download();
    s.mode = C.pair_mode.download();
    if (checking) s.near = bc().near.download();
    s.work = bond_work;
    s.stored = bond_stored;
    s.dissipation_effective = bond_dissipation;
    s.checks = bond_checks;
    m.restore_bonds(s);
  }
};

DeviceStep::DeviceStep(Model& m) : impl_(new Impl) {
  m.step(0);  // prepared as Model::step prepares it: parameters, masses, dt against the stable step
  const Model& cm = m;  // the read access (a Model's writable views are its own)
  if (cm.parameters().sleep.on) bad("the GPU step does not run the sleeping far field: set sleeping=False");
  Impl& d = *impl_;
  d.contact = cm.contact_possible();
  d.bonded = cm.bonds().n_points() > 0;
  d.checking = d.bonded && cm.bonds().params().check_failure;
  if (d.bonded && !d.contact)  // a bond joins two bodies: cannot happen
    bad("the GPU step: a model with bond points and a single body");
  d.reach_guard = d.contact && std::isfinite(cm.parameters().contact_reach);
  d.reach_half = 0.5 * cm.parameters().contact_reach;
  if (d.contact) m.evaluate();  // a candidate list at this state (the warm start left as it was)
  d.model = &m;
  d.make_stages();
  d.dt = m.dt();
  d.time = m.time();
  d.step_count = m.step_count();
  d.energy = m.energy();
}

DeviceStep::~DeviceStep() {
  Impl& d = *impl_;
  d.release_stages();
  d.destroy_graph();
  if (d.host_records) cudaFreeHost(d.host_records);
  if (d.host_values) cudaFreeHost(d.host_values);
  if (d.host_counts) cudaFreeHost(d.host_counts);
}

void DeviceStep::step(int64_t n) {
  if (n < 0) bad("n (number of steps) must be >= 0");
  impl_->advance(n);
}

void DeviceStep::download(Model& m) {
  Impl& d = *impl_;
  if (&m != d.model) bad("download: not the model the GPU step was made from");
  d.to_model();
  // the last step's reactions (a run's indenter force) and the elements'
  // stresses (its fields): the stresses at the state the steps ended in,
  // which the next step's prologue computes (after a remake: run it now)
  if (!d.primed) d.prime();
  m.restore_step_fields(d.u().r_x.download(), d.u().r_y.download(), d.f().stress.download());
}

void DeviceStep::reaction(const std::vector<int32_t>& nodes, double& rx, double& ry) {
  Impl& d = *impl_;
  cuda_check(cudaStreamSynchronize(d.stream), "GPU step");
  // after a step the model took, its reactions are the ones
  Model::sum_reactions(d.u().r_x.download(), d.u().r_y.download(), nodes, rx, ry);
}

double DeviceStep::time() const { return impl_->time; }
int64_t DeviceStep::step_count() const { return impl_->step_count; }
int64_t DeviceStep::host_steps() const { return impl_->host_steps; }
double DeviceStep::host_step_seconds() const { return impl_->host_step_seconds; }
double DeviceStep::make_seconds() const { return impl_->make_seconds; }
int64_t DeviceStep::list_rebuilds() const { return impl_->list_rebuilds; }
double DeviceStep::list_seconds() const { return impl_->list_seconds; }
int64_t DeviceStep::remakes() const { return impl_->remakes - 1; }  // the first making is not a remake
int64_t DeviceStep::graph_instantiations() const { return impl_->graph_instantiations; }
int64_t DeviceStep::graph_updates() const { return impl_->graph_updates; }
int64_t DeviceStep::colourings() const { return impl_->colourings(); }
const EnergyLedger& DeviceStep::energy() const { return impl_->energy; }

}  // namespace engine
