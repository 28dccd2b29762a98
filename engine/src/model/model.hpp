// The FEM-DEM model: deformable blocks (CST), contact, external forces and
// explicit central-difference time stepping. Model::advance() is the time step
// of docs/model.md §3, one call per physical step.
#pragma once
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "loads/boundary_conditions.hpp"
#include "contact/contact.hpp"
#include "element/cst_element.hpp"
#include "model/energy.hpp"
#include "model/gather_kernel.hpp"
#include "model/update_kernel.hpp"
#include "model/gather_plan.hpp"
#include "model/step_sums.hpp"
#include "loads/external_forces.hpp"
#include "bonds/bond_host.hpp"
#include "bonds/freeze_bonds.hpp"
#include "element/material.hpp"
#include "common/mesh_arrays.hpp"
#include "model/sleeping.hpp"
#include "model/time_step.hpp"
#include "model/engine_parameters.hpp"

namespace engine {

// A run stopped because it went unstable (non-finite values, an inverted
// element, or energy growing without a source). Python: icerubble._engine.InstabilityError.
struct InstabilityError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Wall time spent in each part of the step [s], cumulative.
struct StepTimings {
  double elements = 0.0;           // element and body forces, gather onto nodes
  double drag = 0.0;               // of which the bodies' quadratic drag constants
  double contact_detection = 0.0;  // as reported by the contact module
  double contact_forces = 0.0;     // rest of the contact calls (normal + friction)
  double friction = 0.0;           // of which friction (eq 4: its islands, colouring, sweeps)
  double bonds = 0.0;              // freeze-bond check and cohesive forces
  double integration = 0.0;        // boundary conditions, update, energy, checks
  double total = 0.0;
  int64_t steps = 0;
  int64_t element_steps = 0;       // triangles computed, summed over steps
  // The element pass by thread (index: the thread's number in its team):
  // time in its own triangles and their gathers, and time waiting at the
  // pass's barrier for the others. Their spread says whether a team's pass
  // is held back by one thread (imbalance) or slowed in every thread alike.
  std::vector<double> element_busy, element_wait;
};

// The stability guard's two energy checks on a ledger (Model::guard_stability).
struct EnergyAlarm {
  bool growth = false;     // (b) stored energy above kGrowthFactor x every energy flow
  bool imbalance = false;  // (a) balance residual above energy_tolerance x the scale
  double excess = 0.0, flows = 0.0, residual = 0.0, scale = 0.0;
  bool fires() const { return growth || imbalance; }
};

class Model final : public BondHost {
 public:
  // xy: 2 per node; tri: 3 node ids per triangle, counter-clockwise; body: per
  // triangle, ids 0..n_bodies-1. Throws std::invalid_argument on bad input.
  Model(const std::vector<double>& xy, const std::vector<int32_t>& tri,
        const std::vector<int32_t>& body);

  // --- parameters (each setter validates and names the valid range) ---
  void set_material(int32_t body, const Material& m);
  // An explicit time step [s]; switches a dt fraction off.
  void set_dt(double dt);
  // dt = f x the stable step of the model as prepared now (masses scaled,
  // topology current), f in (0, 1]. It stays fixed afterwards (bond splits
  // and later parameter changes do not move it), as a run's dt always has:
  // call again to re-derive. dt_fraction() is 0 while an explicit dt is in force.
  void set_dt_fraction(double f);
  double dt_fraction() const { return dt_fraction_; }
  // Every other parameter (engine_parameters.hpp), all at once: checked here,
  // once, against the registry's ranges (std::invalid_argument naming the
  // parameter and its range); what a changed value makes stale (stable step,
  // masses, sleeping state) is dropped. Among them: local damping (Cundall:
  // each free force component reduced by alpha |f| when it pushes along the
  // velocity, raised when against it; for reaching rest, its work booked as
  // damping), selective mass scaling (the inertial mass of the nodes that
  // limit the stable step raised until it is at least mass_scaling_dt; weight
  // stays physical, Nodes::mass_phys), the contact reach (how far a boundary
  // edge looks for the boundaries it can meet when the contact stable step is
  // bounded; infinite: the whole mesh; with a finite reach the step is
  // re-checked whenever a node has moved more than reach/2 since the last
  // bound, and a run whose dt no longer holds stops with an InstabilityError
  // saying so) and the sleeping far field (sleeping.hpp; switching it on or
  // off wakes every node). A model runs only once it has been given them.
  void set_parameters(const EngineParameters& p);
  const EngineParameters& parameters() const { return params_; }
  // Throws std::invalid_argument unless set_parameters has been called.
  void require_parameters() const;
  double mass_scaling() const { return params_.mass_scaling_dt; }
  // Every node awake, quiet counters reset, pending body wakes cleared and
  // the balance window closed (the next update opens a new one).
  void wake_all();
  // The sleep state of every node and the open balance window (a
  // checkpoint), and its restore. Throws std::invalid_argument on a size or
  // value out of range.
  SleepState sleep_state() const;
  void restore_sleep_state(const SleepState& state);
  // Per-node mass floors [kg/m] (a checkpoint's Nodes::mass_floor). Throws
  // std::invalid_argument on a size or a negative or non-finite value.
  void set_mass_floor(const std::vector<double>& floor);
  // After a phase at a larger mass-scaling step (the settle's dynamic
  // relaxation) and mass_scaling_dt (set_parameters) and dt back to the smaller one: drops the
  // mass floors the larger step raised, takes the masses of the current
  // target, books the kinetic energy this changes as damping, and raises the
  // nodes the present configuration needs for the current dt (blocks now
  // within contact reach of stiffer boundaries). Returns the nodes raised.
  int32_t reset_contact_masses();
  int32_t raised_nodes() const { return raised_nodes_; }
  // Where the contact reach guard measures each node's move from (the node
  // positions of the last contact step bound; a checkpoint), and its restore.
  // Throws std::invalid_argument unless both have as many entries, at most
  // one per node (nodes split off since the last bound have none yet).
  // With a finite contact_reach, every kReachCheckEvery steps (advance):
  // re-bound the contact step once a node has moved past reach/2 from its
  // origin (and raise masses, or stop, as the new bound needs). Public for
  // the GPU step, whose test runs on the GPU and which lets the model do this.
  static constexpr int64_t kReachCheckEvery = 64;
  void guard_contact_reach();
  // After every step (advance): stop with InstabilityError, saying where, on
  // non-finite energies or values, energy growing without a source
  // (energy_alarm, with check_energy on) or an inverted element. Public for
  // the GPU step, which books the ledger on the host, tests energy_alarm
  // itself and lets the model say where.
  void guard_stability();
  EnergyAlarm energy_alarm(const EnergyLedger& E) const;
  // Gives the nodes split off since the last bound their origins: their
  // reference places (the guard and the stable step do it before they read them).
  void extend_reach_origin();
  const std::vector<double>& reach_origin_x() const { return reach_x_; }
  const std::vector<double>& reach_origin_y() const { return reach_y_; }
  void set_reach_origin(const std::vector<double>& x, const std::vector<double>& y);
  int32_t asleep_nodes() const;
  // Triangles the next force evaluation computes (all of them unless sleeping).
  int32_t awake_triangles();

  // --- boundary conditions ---
  void add_boundary_condition(const BoundaryCondition& bc);
  void clear_boundary_conditions();
  // Sum of the forces the boundary conditions exert on these nodes [N/m]
  // (what the boundary pushes with), from the last step.
  void reaction(const std::vector<int32_t>& nodes, double& rx, double& ry) const;
  // ... the same sum over per-node reactions held elsewhere (the GPU step's,
  // read back): one sum, in the order of `nodes`, for both backends
  static void sum_reactions(const std::vector<double>& r_x, const std::vector<double>& r_y,
                            const std::vector<int32_t>& nodes, double& rx, double& ry);
  int32_t find_boundary_condition(const std::string& name) const;

  // --- state ---
  void set_positions(const std::vector<double>& x, const std::vector<double>& y);
  void set_velocities(const std::vector<double>& vx, const std::vector<double>& vy);

  // --- running ---
  void step(int64_t n);  // n time steps (checks dt and inputs first)
  // Forces (1)-(6) and boundary reactions at the current state, no update.
  void evaluate();
  // Stages (1)-(3) only, at the current state: the node forces as the
  // cohesive pass (5) reads them (f_x: elements, gravity, water; f_con:
  // normal contact). The GPU's cohesive stage is compared from here
  // (docs/gpu.md); evaluate() or the next step computes every stage again.
  void evaluate_before_cohesive();
  // The contact candidate list built at the current positions, as the next
  // step's contact pass would build it (the mesh changed since the last
  // one): the GPU step's split steps, whose stages start from it; no force
  // is computed.
  void build_contact_list();
  StableStep stable_step();
  void reset_energy();
  // Continue the bookkeeping of a checkpointed run (after positions/velocities are set).
  void restore_energy(const EnergyLedger& e) { energy_ = e; }
  // Continue the clock of a checkpointed run. Throws std::invalid_argument
  // unless time is finite and step_count >= 0.
  void restore_clock(double time, int64_t step_count);
  // What a step computed besides the state, taken on another device (the
  // GPU step's download): the boundary reactions per node and the elements'
  // stresses, so that reaction() and stress read the last step's. Throws
  // std::invalid_argument on arrays of the wrong size.
  void restore_step_fields(const std::vector<double>& r_x, const std::vector<double>& r_y,
                           const std::vector<double>& stress);

  // --- topology editing for freeze-bond node splitting ---
  int32_t add_node(double x, double y, double x0, double y0, double vx, double vy);
  void set_triangle_node(int32_t tri, int corner, int32_t node);
  // Masses, gather list, boundary nodes, surface triangles; call after edits.
  void rebuild_topology();
  // rebuild_topology + masses + constraint masks if anything changed
  // (validates materials); step() and stable_step() call it.
  void prepare_topology() override;
  // Node splitting (freeze bonds): a new node at `node`'s place and velocity
  // takes over the corners of `body`'s triangles at `node`, and joins every
  // boundary condition holding `node` (a prescribed node stays prescribed on
  // every side). Returns its id; prepare_topology() then rebuilds the rest.
  int32_t split_off(int32_t node, int32_t body) override;
  // Recompute one node's sum of this step's corner forces, gravity and drag
  // (after a split gave it its own corners).
  void regather_node(int32_t node) override;
  // After prepare_topology() recomputed the masses of a split: with mass
  // scaling the pieces of a split node need not add up to its inertial mass
  // (each side keeps the contact mass the node needed). Keeps the momentum of
  // every node whose mass changed (with the nodes split off it: m_before
  // holds the masses of the nodes before the split, split_parent the parent
  // of each node added since, in order) and books the kinetic energy this
  // changes as damping. Returns the nodes whose mass changed.
  int32_t keep_momentum_through_split(const std::vector<double>& m_before,
                                      const std::vector<int32_t>& split_parent) override;
  // (kSameMass, the masses' round-off: bonds/bond_host.hpp)
  // Some triangle of `body` has a corner at `node`.
  bool node_touches_body(int32_t node, int32_t body) const override;

  // --- read access (the state changes only through the methods above and
  // the step's own stages; FreezeBonds, the topology stage's collaborator,
  // writes its forces and splits through its host interface, bonds/bond_host.hpp) ---
  const Nodes& nodes() const override { return nodes_; }
  const Triangles& triangles() const override { return tris_; }
  // Node -> triangle corners, in the fixed order of every per-node sum.
  const NodeGather& gather() const override { return gather_; }
  int threads() const override { return params_.threads; }  // 0: OpenMP default
  // the threads a step's sums are split over (what their rounding depends on)
  int thread_count() const;
  const std::vector<int32_t>& surface_triangles() const { return surface_tris_; }
  const std::vector<uint8_t>& surface_nodes() const { return on_surface_; }
  const EnergyLedger& energy() const { return energy_; }
  const StepTimings& timings() const { return timings_; }
  const std::vector<BoundaryCondition>& boundary_conditions() const { return bcs_; }
  const std::vector<Material>& materials() const { return materials_; }
  const std::vector<double>& body_area0() const { return body_area0_; }
  const std::vector<ElementMaterial>& element_materials() const { return elem_mat_; }
  const BodyTriangleLists& body_triangles() const { return body_tris_; }
  bool any_damping() const { return any_damping_; }
  double local_damping() const { return params_.local_damping; }
  const ContactSolver& contact() const { return contact_; }
  // A checkpoint's friction history (the stick forces the next step starts from).
  void set_contact_warm_start(const std::vector<uint64_t>& keys, const std::vector<double>& forces) {
    contact_.set_warm_start(keys, forces);
  }
  int32_t n_bodies() const override { return int32_t(materials_.size()); }
  double time() const override { return time_; }
  int64_t step_count() const override { return step_count_; }
  double dt() const override { return dt_; }
  const ExternalParams& external() const { return params_.external; }
  const ContactParams& contact_params() const override { return params_.contact; }
  double energy_tolerance() const { return params_.energy_tolerance; }
  bool check_stable_dt() const { return params_.check_stable_dt; }
  // The mesh has two bodies or more: the contact stages run.
  bool contact_possible() const { return contact_possible_; }
  int32_t touching_pairs() const { return contact_.touching_pairs(); }
  int64_t contact_list_builds() const { return contact_.rebuilds(); }  // broad-phase builds so far
  size_t memory_bytes() const;

  // --- freeze bonds (freeze_bonds.hpp; splitting edits the topology) ---
  const FreezeBonds& bonds() const { return bonds_; }
  // The bond points (validated against the mesh first; only while none has
  // split, or for_restore), their parameters, and a checkpoint's state.
  void set_bonds(const BondInput& in, bool for_restore) { bonds_.set(*this, in, for_restore); }
  void set_bond_params(const BondParams& p) { bonds_.set_params(p); }
  void restore_bonds(const BondState& s) { bonds_.restore(*this, s); }

 private:
  Nodes& bond_nodes() override { return nodes_; }  // the bonds' writes (BondHost)
  Nodes& nodes() { return nodes_; }
  Triangles& triangles() { return tris_; }
  ContactSolver& contact() { return contact_; }
  FreezeBonds& bonds() { return bonds_; }

  // Whether a force evaluation moves history on (bond splits, cohesive
  // pairs' damage and events) or only looks at the current state.
  enum class History { commit, leave };

  // The time step, docs/model.md §3: compute_forces(commit), then the update.
  void advance();
  void compute_forces(History history);
  // one node's sums of corner forces + gravity and drag (also after a split)
  void gather_node(int32_t i, bool damping, bool water, bool buoy, bool drag, double g);
  GatherArrays gather_arrays(bool damping, bool water, bool buoy, bool drag, double g);
  void compute_body_forces();       // (1) elements and (6) gravity, buoyancy, drag
  void compute_contact_forces();    // (2) neighbour search, (3) normal contact
  SplitPlan check_freeze_bonds();   // (4) hook: bond stress check (eqs 5-7), reads only
  void apply_topology_changes(const SplitPlan& plan);  // (4) its node splitting
  void apply_cohesive_forces(History history);  // (5) hook: cohesive forces of opened bonds
  void assemble_forces();           // total force before friction
  void apply_friction(History history);  // (3b) friction, once all other forces are known
  void apply_boundary_conditions(); // fixed nodes, prescribed velocities
  void update_positions();          // (7) central difference + work integration
  UpdateArrays update_arrays(double dt, double g, double alpha);  // model/update_kernel.hpp
  void rebuild_awake_triangles();  // the list of triangles with a corner not long asleep
  void update_sleep();             // after an update: wake woken bodies, sleep bodies at rest
  void open_sleep_window();
  void body_momenta(const std::vector<double>& cx, const std::vector<double>& cy, std::vector<double>& px,
                    std::vector<double>& py, std::vector<double>& l) const;
  // ... and, with mass scaling on, raise the nodes the contact stiffness of the
  // current configuration (`now`) needs
  int32_t raise_contact_masses(const ContactStiffness& now);
  void report_added_mass();        // the mass scaling's totals into stable_
  // v *= factor at node i; returns the energy the books must take as damping
  // beyond the kinetic energy (the shift of the ledger's half-step point)
  double rescale_velocity(int32_t i, double factor);

  bool use_threads() const;
  void prepare();           // everything below + stable step + thread buffers
  void compute_element_limits();  // element_dt0_, kept through bond splits
  void compute_masses();
  void scale_masses();  // the mass scaling part of compute_masses
  void build_constraints();
  ContactInput contact_input() const;
  ContactInput reference_contact_input() const;
  // The contact stiffness of the reference configuration, computed once per
  // topology, reach and penalty: the masses and the stable step both need it
  // after every bond event.
  const ContactStiffness& reference_contact_stiffness();
  [[noreturn]] void fail(const std::string& what, int32_t node, int32_t tri) const;
  int32_t body_of_node(int32_t node) const;

  Nodes nodes_;
  Triangles tris_;
  NodeGather gather_;
  uint64_t topology_version_ = 0;  // counts rebuild_topology() calls
  GatherPlan gather_plan_;          // gathers in the element pass (gather_plan.hpp)
  std::vector<Material> materials_;
  std::vector<ElementMaterial> elem_mat_;
  // each triangle's undamped limit and the materials it was taken with (compute_element_limits)
  std::vector<double> element_dt0_;
  std::vector<ElementMaterial> element_dt0_mat_;
  std::vector<double> body_area0_;
  std::vector<double> body_drag_;  // each body's drag constant this step [N s/m per m]
  std::vector<uint8_t> on_surface_;  // node lies on its body's boundary
  std::vector<int32_t> surface_tris_;
  BodyTriangleLists body_tris_;  // per body: its triangles, its surface triangles
  bool contact_possible_ = false;
  bool any_damping_ = false;

  std::vector<BoundaryCondition> bcs_;
  // every parameter but the materials and dt (set_parameters); NaN until set
  EngineParameters params_;
  bool parameters_set_ = false;
  ContactSolver contact_;
  double dt_ = 0.0;
  double dt_fraction_ = 0.0;  // 0: dt_ was set explicitly (or not at all)
  double added_mass_ = 0.0;       // sum of mass - mass_phys [kg/m]
  double total_mass_phys_ = 0.0;
  int32_t scaled_nodes_ = 0;
  int32_t raised_nodes_ = 0;      // node mass raises by the reach guard so far (this process)
  std::vector<double> reach_x_, reach_y_;  // node positions of the last contact step bound
  ContactStiffness ref_stiffness_;
  // the bond splits since ref_stiffness_ was taken (split_off), applied to it
  // instead of taking it again; any other edit of the corners makes it stale
  // (a model starts stale: nothing taken yet)
  std::vector<ShareRename> ref_stiffness_renames_;
  bool ref_stiffness_stale_ = true;
  double ref_stiffness_reach_ = 0.0, ref_stiffness_penalty_ = 0.0;
  std::vector<int32_t> awake_tris_;  // computed triangles while sleeping is on
  std::vector<int32_t> node_body_;   // the body of each node's first corner (its sleeping unit)
  std::vector<uint8_t> body_wake_;   // bodies a node woke in this update
  SleepWindow window_;
  bool awake_current_ = false;       // awake_tris_ matches the nodes' sleep states
  // A restored model has no stored forces yet: its first evaluation computes
  // every triangle (the sleeping ones at their frozen place, as before).
  bool compute_all_next_ = false;

  bool prepared_ = false;  // masses, stable step and constraints are current
  StableStep stable_;
  bool stable_current_ = false;

  double time_ = 0.0;
  int64_t step_count_ = 0;
  EnergyLedger energy_;
  double contact_work_step_ = 0.0;
  int32_t first_inverted_ = -1;
  StepTimings timings_;
  std::vector<ThreadSums> partial_;  // per-thread sums, reduced in thread order
  FreezeBonds bonds_;
};

}  // namespace engine
