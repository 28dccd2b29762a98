// Contact between triangles of different bodies: the interface between the
// engine (the Model, which owns the node arrays) and the contact module.
//
// Two passes per step, so that friction can see every other force:
//   1. compute_normal(): broad phase + Munjiza potential contact forces
//      (docs/model.md §3.2, eqs 1-3). Adds the normal (penalty) forces to fx, fy and
//      remembers, for every touching pair, where and how hard it pushes.
//   2. apply_friction(): after all other forces of the step are assembled,
//      dynamic Coulomb friction (eq 4) on the pairs of pass 1, regularised at
//      zero slip so that a block below the friction angle stays at rest.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

#include "contact/broad_phase.hpp"
#include "contact/friction_order.hpp"
#include "contact/potential_contact.hpp"

namespace engine {

// No defaults here: they are the registry's (icerubble/parameters.py).
struct ContactParams {
  double penalty = NAN;  // s in eq 2-3 [Pa, per unit width]
  double mu = NAN;       // Coulomb friction coefficient [-]
};

// The one check of the contact parameters against the registry's ranges,
// where they enter (Model::set_parameters and the ContactSolver bindings);
// the per-step calls trust them. Throws std::invalid_argument (ValueError in
// Python) naming the parameter and its valid range.
void validate(const ContactParams& p);
ContactParams validated_contact_params(double penalty, double mu);

// Views of the engine's flat node and element arrays (structure of arrays).
struct ContactInput {
  int32_t n_nodes = 0;
  const double* x = nullptr;    // node positions [m]
  const double* y = nullptr;
  const double* vx = nullptr;   // node velocities at t - dt/2 [m/s]
  const double* vy = nullptr;
  const double* mass = nullptr; // lumped node masses [kg per m width]; a node
                                // with mass <= 0 or inf is immovable (friction)
  int32_t n_tri = 0;
  const int32_t* tri = nullptr;   // 3 node ids per triangle, counter-clockwise
  const int32_t* body = nullptr;  // body id per triangle
  // Triangles that can touch another body (a node on their body's boundary);
  // the broad phase looks at nothing else.
  int32_t n_surface = 0;
  const int32_t* surface_tris = nullptr;
  double dt = 0.0;
  int32_t threads = 0;  // OpenMP threads for the contact passes; 0: OpenMP default
  // The host's count of its topology changes (triangles, bodies, surface
  // list), if it keeps one; 0: unknown, the solver then hashes the topology
  // every step to see whether its candidate list still belongs to it.
  uint64_t topology_version = 0;
  // Optional kinematic constraints (nullptr: none). constrained[n] bit 0: vx
  // prescribed, bit 1: vy prescribed. Friction treats a prescribed component
  // as immovable, moving at v_bc (the prescribed velocity at t + dt/2) if
  // given, else at its current velocity vx, vy.
  const uint8_t* constrained = nullptr;
  const double* v_bc_x = nullptr;
  const double* v_bc_y = nullptr;
};

// A touching triangle pair of the last compute_normal call: where the
// resultant normal force acts and how large it is (input of friction, eq 4).
struct ContactPair {
  int32_t contactor = 0, target = 0;  // triangle ids (contactor < target)
  int32_t node[6] = {0, 0, 0, 0, 0, 0};  // contactor nodes, then target nodes
  double nc[3] = {0, 0, 0};  // contactor shape functions at the contact point
  double nt[3] = {0, 0, 0};  // target shape functions at the contact point
  double px = 0, py = 0;     // contact point: centroid of the overlap [m]
  double nx = 0, ny = 0;     // unit normal: direction of the force on the contactor
  double fn = 0;             // |f_c|, magnitude of the normal force [N per m width]
  double energy = 0;         // stored energy of the pair [J per m width]
};

// Cumulative wall time since the solver was made [s].
struct ContactTimings {
  double detection_s = 0.0;  // broad phase (bounding-box candidates)
  double forces_s = 0.0;     // pair kernel (incl. rejecting non-overlapping candidates), friction
};

// Stability limit of the explicit scheme set by the contact penalty.
// A boundary edge of length l on a triangle of altitude a (onto that edge),
// pressed flat onto another body's edge of altitude a', stores
// E = 3/2 s l d^2 (1/a + 1/a') at overlap depth d (each potential grows as
// 3 depth/altitude). Half of that edge stiffness goes to each end node, so a
// boundary node i gets
//   k_i = 3/2 s sum_{boundary edges e at i} (l_e/a_e + T(l_e)),
// T(l) standing in for the unknown other body: the largest integral of 1/a'
// over any stretch of length l of any body's boundary, or over two stretches
// whose lengths add up to l (an edge across a junction of blocks, where the
// tiny elements are; contact_time_step.cpp).
// On a regular mesh T(h) = 1, i.e. l/a'; a sliver counts only over its own
// edge, not over the whole contactor edge (the smallest altitude anywhere,
// l_e/a_min, made one 2 mm sliver set the step of every node). Two facing nodes vibrate at w^2 = k_i/m_i + k_j/m_j <= 2 max k/m,
// so the critical step is dt = 2/w = min_i sqrt(2 m_i / k_i). On a regular
// mesh (l = a = h) k = 6 s at every boundary node, six times the single-spring
// estimate k = s. Head-on collisions of two 1 m x 0.5 m blocks (h = 0.1 m,
// s = 2e11, limit 1.6 us) conserve energy to 0.4 % at 1.2 times this step and
// gain 4 % at 1.3 times, 18 % at 1.4 times (there a corner touches a face with
// one of its two edges only, k = 3 s; the bound covers corner-on-corner too).
struct ContactStableStep {
  double dt = 0.0;        // critical step, no safety factor [s] (inf: no boundary)
  int32_t node = -1;      // governing node
  double stiffness = 0.0; // its k_i [N/m per m width]
  double mass = 0.0;      // its m_i [kg per m width]
};
// Uses tri, body, n_tri, x, y and mass of `in`. Each body is taken on its own
// (boundary edges: used by one triangle of the body; a node shared by bodies,
// i.e. a freeze-bond point, counts per body with that body's mass share), so
// the limit also holds after every bond point has split.
// Throws std::invalid_argument on bad p.
// node_stiffness (optional, resized to n_nodes): per node, the largest over its
// bodies of k_i scaled to the node's whole mass (k_i x node area / that body's
// area around it), so that node n's limit is sqrt(2 mass[n] / node_stiffness[n]);
// 0 for an interior node. For mass scaling (EngineParameters::mass_scaling_dt).
// reach (m, > 0; infinite: the whole mesh): an edge counts only the other
// bodies' boundary it can meet, the stretches within reach of it now (see
// contact_time_step.cpp); valid while no node has moved farther than reach/2
// relative to that (Model::set_parameters keeps it so).
ContactStableStep contact_critical_dt(const ContactParams& p, const ContactInput& in,
                                      std::vector<double>* node_stiffness = nullptr,
                                      double reach = INFINITY);

// contact_critical_dt in its two parts: the stiffness of each (node, body),
// which takes the geometry and is the cost of it (sorting every edge, walking
// every boundary), and the step of given masses, a pass over those entries.
// The model takes the step of its reference configuration twice per bond
// event (for the masses, then for the step with them): the stiffness is
// computed once for both. The result is that of contact_critical_dt, bit for bit.
struct ContactStiffness {
  std::vector<int32_t> node, body;  // per (node, body) with a share of the node: ascending node, then body
  std::vector<double> k, area;   // its stiffness [N/m per m] and area around the node [m²]
  std::vector<double> node_area; // per node: area of all its triangles [m²] (n_nodes entries)
};
ContactStiffness contact_stiffness(const ContactParams& p, const ContactInput& in, double reach = INFINITY);
// A bond split gives node `node`'s triangles of body `body` a new node `id`
// at the same place: the stiffness of the split mesh is s with those entries
// renamed, bit for bit (contact_stiffness takes every figure in triangle
// order), and its node areas taken again from `in`, the split mesh. Renames
// apply in order (a node split off may split again). Throws std::logic_error
// where s has no such entry (s is not of the mesh before the splits).
struct ShareRename {
  int32_t node, body, id;
};
void rename_contact_shares(ContactStiffness& s, const std::vector<ShareRename>& renames, const ContactInput& in);
ContactStableStep contact_critical_dt(const ContactStiffness& s, const double* mass,
                                      std::vector<double>* node_stiffness = nullptr);

class ContactSolver {
 public:
  // Adds normal contact forces to fx, fy (length n_nodes). Returns the number
  // of touching triangle pairs.
  int32_t compute_normal(const ContactParams& p, const ContactInput& in, double* fx, double* fy);
  // Adds friction forces to fx, fy, given the forces already assembled there
  // (used to predict the sliding velocity). Returns the friction power
  // (dissipation rate, >= 0) [W per m width].
  double apply_friction(const ContactParams& p, const ContactInput& in, double* fx, double* fy);
  // Contact potential energy at the positions of the last compute_normal call
  // [J per m width]: sum over touching pairs of s * int_overlap (phi_c + phi_t),
  // whose exact gradient the normal forces are (potential_contact.hpp). A state
  // value like the elastic energy: add it to the energy balance as it is, do
  // not accumulate it over steps.
  double stored_energy() const { return stored_energy_; }
  int32_t touching_pairs() const { return n_touching_; }
  const ContactTimings& timings() const { return timings_; }
  const std::vector<ContactPair>& pairs() const { return pairs_; }
  // Friction warm start (last step's tangential force per (contactor, target)
  // key, keys sorted): part of a checkpoint, so a resumed run continues exactly.
  const std::vector<uint64_t>& warm_start_keys() const { return prev_key_; }
  const std::vector<double>& warm_start_forces() const { return prev_lambda_; }
  // The last apply_friction call: its pairs' tangential forces (pair order)
  // and the order its sweeps took (for the GPU backend's comparison).
  std::vector<double> friction_forces() const {
    return std::vector<double>(lambda_.begin(), lambda_.begin() + std::min(lambda_.size(), pairs_.size()));
  }
  const FrictionOrder& sweep_order() const { return order_; }
  double friction_power() const { return friction_power_; }  // its return value
  void set_warm_start(const std::vector<uint64_t>& keys, const std::vector<double>& forces) {
    prev_key_ = keys;
    prev_lambda_ = forces;
  }
  // Bounding-box candidates of the last broad phase (diagnostics and tests).
  const std::vector<CandidatePair>& candidates() const { return candidates_; }
  // Candidate reuse: boxes are grown by skin_fraction times the largest
  // surface-triangle extent, and the list is rebuilt only when a node of a
  // surface triangle has moved farther than that (or the surface triangles,
  // their nodes or bodies changed). 0: rebuild every call.
  void set_skin_fraction(double f);
  double skin_fraction() const { return skin_fraction_; }
  int64_t rebuilds() const { return rebuilds_; }  // broad-phase builds so far
  // The candidate list built at in's positions now, as compute_normal builds
  // it when the list is stale (Model::build_contact_list: the list the GPU
  // step's stages start from after a split, cuda/device_step.cu).
  void build_list(const ContactInput& in);
  // The candidate list's validity as list_still_valid tests it (the GPU
  // step tests it on the GPU): the node positions it was built at and its
  // skin [m] (0 without a list: no move keeps it).
  const std::vector<double>& list_origin_x() const { return xref_; }
  const std::vector<double>& list_origin_y() const { return yref_; }
  double list_skin() const { return have_list_ && skin_fraction_ > 0.0 ? broad_.skin() : 0.0; }

 private:
  bool list_still_valid(const ContactInput& in) const;

  double stored_energy_ = 0.0;
  int32_t n_touching_ = 0;
  ContactTimings timings_;
  // Buffers reused from step to step (no allocation once they have grown).
  BroadPhase broad_;
  std::vector<CandidatePair> candidates_;  // (contactor, target) order: the touching pairs come in it
  double skin_fraction_ = 0.1;
  int64_t rebuilds_ = 0;
  bool have_list_ = false;
  uint64_t list_signature_ = 0;     // surface triangles, nodes, bodies of the list
  uint64_t list_topology_ = 0;      // the host's topology_version of the list (0: unknown)
  std::vector<double> xref_, yref_; // node positions when the list was built
  std::vector<PairContact> results_;
  std::vector<std::vector<int64_t>> chunk_hits_;  // each candidate chunk's touching candidates, ascending
  std::vector<ContactPair> pairs_;
  std::vector<double> wx_, wy_, imx_, imy_, lambda_;  // friction workspace
  double friction_power_ = 0.0;
  struct SweepPair {  // a pair as the sweeps read it, in sweep order (friction.cpp)
    int32_t node[6];
    double nc[3], nt[3], nx, ny, limit, kinv, lambda;
    bool fn_zero;
  };
  std::vector<SweepPair> sweep_;
  std::vector<int32_t> slot_;        // sweep_[s] holds pair slot_[s] (island by island)
  std::vector<int32_t> slot_of_;     // and pair i is in sweep_[slot_of_[i]]
  struct IslandNodes {               // an island's nodes and their friction values, a thread's
    std::vector<int32_t> node;       // the mesh's number of each
    std::vector<double> wx, wy, imx, imy;
  };
  std::vector<IslandNodes> island_nodes_;  // one per thread
  std::vector<int32_t> local_of_;    // a node's number in its island's arrays (-1 between calls)
  std::vector<double> slip_work_;    // lambda times the end-of-step slip, per pair
  std::vector<int32_t> pair_nodes_;  // six nodes per pair, pair order
  std::vector<uint64_t> pair_keys_;  // (contactor, target) per pair, ascending
  FrictionIslands islands_;          // the pairs' islands (where threads share them)
  bool islands_of_pairs_ = false;    // islands_ are those of pairs_
  std::vector<int32_t> island_owner_; // their workspace
  FrictionOrder order_;              // the sweeps' order of the last friction call
  std::vector<uint64_t> order_used_; // its workspace
  std::vector<int64_t> hits_;       // touching candidates, in pair order
  std::vector<uint64_t> prev_key_;  // (contactor, target) of last step's pairs, sorted
  std::vector<double> prev_lambda_; // their tangential forces (warm start)
};

}  // namespace engine
