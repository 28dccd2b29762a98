// Freeze bonds as initially rigid cohesive elements (Polojärvi & Tuhkuri 2013,
// section 2.3, eqs 5-12; MODEL.md 3.3; docs/freeze_bonds.md).
//
// The mesh is continuous across touching blocks. A bond point is a mesh node on
// a freeze-bond edge; it joins two bodies (one *pair*) or, at a junction, more
// (one pair per two bodies that share a bond edge there). Every step:
//   check():  for each intact bond point the traction t = sum (A_i/A) sigma_i n
//             (eq 7) is tested against the criterion (eqs 5-6); a point that meets
//             it splits (bond_split.cpp): one node per body, masses from the
//             elements on each side, cohesive pairs with f0 from eq 8 and
//             delta_f = 2 G l / f0 (eq 12).
//   apply():  the cohesive force pair of every opened pair (eqs 9-11) is added
//             to nodes.f_coh; full failure and its mode are logged.
// All arrays are structure-of-arrays; bond points and pairs are indexed as given
// by the host (pairs grouped by point, points in any order).
#pragma once
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "cohesive_law/softening.hpp"

namespace engine {

class Model;

// The static description of the bonds, as found from the mesh
// (icerubble/bond_points.py). Pairs must be grouped by point (pair_point
// non-decreasing) and every point needs at least one pair.
struct BondInput {
  // per bond point
  std::vector<int32_t> node;       // mesh node id
  std::vector<double> sigma_cr;    // tensile strength [Pa]
  std::vector<double> tau_cr;      // shear strength [Pa]
  std::vector<double> G;           // fracture energy [J/m²]
  // per pair (a two-body point has one)
  std::vector<int32_t> pair_point;
  std::vector<int32_t> body_minus, body_plus;  // the normal points from - to +
  std::vector<double> nx, ny;                  // bond normal in the reference configuration
  std::vector<double> length;                  // l [m]: half of the pair's bond edges at the node
  // Two nodes whose reference-to-current rotation turns the normal of an
  // intact pair (the ends of its bond edges at the node, or the node and the
  // far end of its only edge).
  std::vector<int32_t> frame_p, frame_q;
};

struct BondParams {
  // Friction coefficient of the compressive branch of eq 6; NaN: use the
  // contact mu (MODEL.md 3.3, the paper's choice).
  double mu = std::numeric_limits<double>::quiet_NaN();
  cohesive_law::ForceDirection direction = cohesive_law::ForceDirection::paper;
  bool check_failure = true;  // off while the scene settles under gravity
  // Pre-screening: an intact point whose largest t_e/sigma_cr was below
  // screen_fraction at its last check is checked only every screen_interval
  // steps (staggered). 1 = check every point every step. A failure is then
  // detected at most screen_interval - 1 steps late (docs/freeze_bonds.md).
  int32_t screen_interval = 8;
  double screen_fraction = 0.5;
};

// Bond state that a checkpoint must carry (everything that changes in a run).
struct BondState {
  double time = 0.0;
  int64_t step_count = 0;
  // per point
  std::vector<int8_t> point_state;  // 0 intact, 1 split
  std::vector<int8_t> near;         // pre-screening flag
  std::vector<double> t_split, x_split, y_split;
  // per pair
  std::vector<int8_t> pair_state;   // 0 intact, 1 opened (cohesive), 2 fully failed
  std::vector<int32_t> node_plus, node_minus;
  std::vector<double> fnx, fny;     // bond frame (normal) frozen at the split
  std::vector<double> f0, delta_f, delta_m;
  std::vector<double> f_n_prev, f_t_prev, d_n_prev, d_t_prev;
  std::vector<double> split_tn, split_tt;
  std::vector<double> t_fail, x_fail, y_fail, dn_fail, dt_fail;
  std::vector<int8_t> mode;
  // split nodes: parent (original) node of every node appended by splitting
  std::vector<int32_t> parent;
  // energy accounts [J/m]
  double work = 0.0, dissipation_effective = 0.0, stored = 0.0;
  int64_t late_detections = 0, checks = 0;
};

class FreezeBonds {
 public:
  // Validates against the model's mesh (ValueError naming the bad entry)
  // before storing anything. Only allowed while no bond has split.
  // for_restore: the model is rebuilt from a checkpoint, so a split point's
  // bodies are no longer at its node; restore() checks the split topology.
  void set(Model& M, const BondInput& in, bool for_restore = false);
  void set_params(const BondParams& p);
  const BondParams& params() const { return params_; }
  void clear();

  // Engine hooks (Model::check_freeze_bonds / apply_cohesive_forces).
  void check(Model& M);
  void apply(Model& M);

  // Checkpoints: state out, and back into a model rebuilt from the exported
  // nodes/triangles with the same set() input (restores the model clock).
  BondState state(const Model& M) const;
  void restore(Model& M, const BondState& s);

  int32_t n_points() const { return int32_t(node_.size()); }
  int32_t n_pairs() const { return int32_t(pair_point_.size()); }
  int32_t n_split() const;
  int32_t n_failed() const;
  const BondInput& input() const { return input_; }
  // Original node of every node appended by splitting (in order of appending).
  const std::vector<int32_t>& parents() const { return parent_; }
  // Traction (t_n, t_t) of each pair at its last check [Pa].
  const std::vector<double>& last_tn() const { return tn_; }
  const std::vector<double>& last_tt() const { return tt_; }
  // Energy: mechanical work done against the cohesive forces (trapezoid of
  // the law), energy now stored on the secant branches, and the effective
  // dissipation sum 1/2 f0 delta_m (G l per fully failed pair).
  double work() const { return work_; }
  double stored() const { return stored_; }
  double dissipation_effective() const { return dissipation_eff_; }
  int64_t late_detections() const { return late_; }
  int64_t checks() const { return checks_; }
  size_t memory_bytes() const;

 private:
  void apply_crack_closure(Model& M);
  static int team_size(const Model& M, int64_t items);
  double mu(const Model& M) const;
  void refresh_lists();
  // Area-weighted elastic Cauchy stress around a node (eq 7).
  void mean_stress(const Model& M, int32_t node, double& sxx, double& syy, double& sxy) const;
  // Current normal of an intact pair: the reference normal turned by the
  // rotation of its frame edge.
  void current_normal(const Model& M, int32_t k, double& nx, double& ny) const;
  // Largest t_e / sigma_cr over the pairs of point p (and the traction of each pair).
  double point_ratio(const Model& M, int32_t p, double mu);
  // bond_split.cpp
  void split_points(Model& M, const std::vector<int32_t>& points);
  void regather(Model& M, int32_t node) const;
  // Eq 8 force on the + node of pair k from this step's forces (x, y): from
  // the elastic element forces (f0) or from all forces (the holding force).
  void split_force(const Model& M, int32_t k, bool elastic, double& gx, double& gy) const;

  BondInput input_;
  BondParams params_;
  bool in_step_ = false;

  // per point
  std::vector<int32_t> node_, first_pair_, n_pairs_;
  std::vector<double> sigma_, tau_, G_, beta_;
  std::vector<int8_t> point_state_, near_, fail_;
  std::vector<double> t_split_, x_split_, y_split_;
  // per pair
  std::vector<int32_t> pair_point_, body_minus_, body_plus_, frame_p_, frame_q_;
  std::vector<double> n0x_, n0y_, d0x_, d0y_, l_;
  std::vector<double> tn_, tt_;  // traction of the last check
  std::vector<int8_t> pair_state_;
  std::vector<int32_t> node_plus_, node_minus_;
  std::vector<double> fnx_, fny_, f0_, delta_f_, delta_m_;
  std::vector<double> f_n_prev_, f_t_prev_, d_n_prev_, d_t_prev_;
  std::vector<double> split_tn_, split_tt_;
  std::vector<double> t_fail_, x_fail_, y_fail_, dn_fail_, dt_fail_;
  std::vector<int8_t> mode_;
  // work lists
  std::vector<int32_t> intact_points_, open_pairs_;
  std::vector<double> fx_pair_, fy_pair_, w_pair_, s_pair_, e_pair_;  // per open pair, this step
  std::vector<int32_t> parent_;  // per node appended by splitting

  double work_ = 0.0, dissipation_eff_ = 0.0, stored_ = 0.0;
  int64_t late_ = 0, checks_ = 0;
};

}  // namespace engine
