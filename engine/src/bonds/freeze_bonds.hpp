// Freeze bonds as initially rigid cohesive elements (Polojärvi & Tuhkuri 2013,
// section 2.3, eqs 5-12; docs/model.md §3.3; docs/freeze_bonds.md).
//
// The mesh is continuous across touching blocks. A bond point is a mesh node on
// a freeze-bond edge; it joins two bodies (one *pair*) or, at a junction, more
// (one pair per two bodies that share a bond edge there). Every step:
//   check():  for each intact bond point the traction t = sum (A_i/A) sigma_i n
//             (eq 7) is tested against the criterion (eqs 5-6); the points that
//             meet it are the step's split plan (the model is not changed);
//   split():  the model's topology stage carries the plan out (bond_split.cpp):
//             one node per body, masses from the elements on each side,
//             cohesive pairs with f0 from eq 8 and delta_f = 2 G l / f0 (eq 12).
//   apply():  the cohesive force pair of every opened pair (eqs 9-11) is added
//             to nodes.f_coh; full failure and its mode are logged.
// All arrays are structure-of-arrays; bond points and pairs are indexed as given
// by the host (pairs grouped by point, points in any order).
#pragma once
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "bonds/bond_check_kernel.hpp"
#include "bonds/bond_host.hpp"
#include "bonds/bond_fields.hpp"
#include "bonds/cohesive_pair_kernel.hpp"
#include "cohesive_law/softening.hpp"

namespace engine {


// The bond points a step's check found at the criterion (eqs 5-7), in the
// order of the intact-point list: what the model's topology stage splits.
struct SplitPlan {
  std::vector<int32_t> points;
  bool empty() const { return points.empty(); }
};

struct BondParams {
  // Friction coefficient of the compressive branch of eq 6; NaN: use the
  // contact mu (docs/model.md §3.3, the paper's choice).
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

class FreezeBonds {
 public:
  // Validates against the model's mesh (ValueError naming the bad entry)
  // before storing anything. Only allowed while no bond has split.
  // for_restore: the model is rebuilt from a checkpoint, so a split point's
  // bodies are no longer at its node; restore() checks the split topology.
  void set(BondHost& M, const BondInput& in, bool for_restore = false);
  void set_params(const BondParams& p);
  const BondParams& params() const { return params_; }
  void clear();

  // Engine hooks, in step order: check() (eqs 5-7) runs only in a committed
  // step and returns the split plan without changing the model (it moves on
  // the bonds' own screening state); split() carries a plan out, called by
  // the model's topology stage (Model::apply_topology_changes); apply()
  // (eqs 9-11) adds the cohesive forces and, if commit, advances the pairs'
  // history, events and energy.
  SplitPlan check(const BondHost& M);
  void split(BondHost& M, const SplitPlan& plan);
  void apply(BondHost& M, bool commit);

  // Checkpoints: state out, and back into a model rebuilt from the exported
  // nodes/triangles with the same set() input. The clock is the model's.
  const BondState& state() const { return st_; }
  void restore(BondHost& M, const BondState& s);

  int32_t n_points() const { return int32_t(in_.node.size()); }
  int32_t n_pairs() const { return int32_t(in_.pair_point.size()); }
  int32_t n_split() const;
  int32_t n_failed() const;
  const BondInput& input() const { return in_; }
  // The check's arrays (bonds/bond_check_kernel.hpp: eq 7's stress, the
  // pairs' normals, eqs 5-6); the tractions go to last_tn()/last_tt().
  BondCheckArrays check_arrays(const BondHost& M) const;
  // The cohesive force kernel's arrays (bonds/cohesive_pair_kernel.hpp): the
  // nodes' state and this step's forces, the pairs' history.
  CohesivePairArrays pair_arrays(const BondHost& M) const;
  // Pairs opened and not yet fully failed, ascending: what apply() steps.
  const std::vector<int32_t>& open_pairs() const { return open_pairs_; }
  // Pairs opened or failed, ascending: those crack closure acts on.
  const std::vector<int32_t>& closing_pairs() const { return closing_pairs_; }
  // The friction coefficient of eq 6's compressive branch: params().mu, or the
  // contact mu where that is NaN.
  double mu(const BondHost& M) const;
  // Bond points not yet split, ascending.
  const std::vector<int32_t>& intact_points() const { return intact_points_; }
  // Original node of every node appended by splitting (in order of appending).
  const std::vector<int32_t>& parents() const { return st_.parent; }
  // Traction (t_n, t_t) of each pair at its last check [Pa].
  const std::vector<double>& last_tn() const { return tn_; }
  const std::vector<double>& last_tt() const { return tt_; }
  // Energy: mechanical work done against the cohesive forces (trapezoid of
  // the law), energy now stored on the secant branches, and the effective
  // dissipation sum 1/2 f0 delta_m (G l per fully failed pair).
  double work() const { return st_.work; }
  double stored() const { return st_.stored; }
  double dissipation_effective() const { return st_.dissipation_effective; }
  int64_t late_detections() const { return st_.late_detections; }
  int64_t checks() const { return st_.checks; }
  size_t memory_bytes() const;

 private:
  static int team_size(const BondHost& M, int64_t items);
  void refresh_lists();
  // bond_split.cpp
  void split_points(BondHost& M, const std::vector<int32_t>& points);
  // Eq 8 force on the + node of pair k from this step's elastic element
  // forces: gives f0 at the split.
  void split_force(const BondHost& M, int32_t k, double& gx, double& gy) const;

  BondInput in_;
  BondParams params_;
  BondState st_;

  // derived from in_ by set()
  std::vector<int32_t> first_pair_, n_pairs_;  // per point: its pairs
  std::vector<double> beta_;                   // per point: tau_cr / sigma_cr
  std::vector<double> n0x_, n0y_, d0x_, d0y_;  // per pair: unit normal, frame edge (reference)
  // scratch of the current step
  std::vector<int8_t> fail_;                   // per point: 0, 1 failing, 2 failing found late
  mutable std::vector<double> tn_, tt_;        // per pair: traction of the last check
  std::vector<int32_t> intact_points_, open_pairs_;
  std::vector<int32_t> closing_pairs_;  // opened or failed, ascending: crack closure's
  std::vector<double> fx_pair_, fy_pair_, w_pair_, s_pair_, e_pair_;  // per open pair
  std::vector<double> f_closure_;       // per closing pair: its force, or kNoClosure
};

}  // namespace engine
