#include "common/input_errors.hpp"
#include "bonds/freeze_bonds.hpp"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "bonds/crack_closure_kernel.hpp"
#include "cohesive_law/criterion.hpp"
#include "model/threading.hpp"

namespace engine {

namespace cl = cohesive_law;

namespace {

// Below this many points (pairs) a pass is a few microseconds and a thread
// team costs more than it saves.
constexpr int32_t kMinParallelItems = 1024;

// A closing pair's f_closure_ where its faces are apart (a force is >= 0).
constexpr double kNoClosure = -1.0;

// kRigidOpening, the rigid phase of an opened pair: bonds/cohesive_pair_kernel.hpp.

}  // namespace

// ---------------------------------------------------------------- setup

int FreezeBonds::team_size(const BondHost& M, int64_t items) {
  if (items < kMinParallelItems) return 1;
  const int t = M.threads() > 0 ? M.threads() : omp_get_max_threads();
  return std::max(1, t);
}

void FreezeBonds::clear() {
  *this = FreezeBonds{};
}

void FreezeBonds::set(BondHost& M, const BondInput& in, bool for_restore) {
  if (!st_.parent.empty())
    bad("bond points can only be set before any bond point has split "
        "(restore a checkpoint to continue a run with split bonds)");
  const int64_t P = int64_t(in.node.size());
  const int64_t K = int64_t(in.pair_point.size());
  const int32_t n = M.nodes().size();
  const int32_t nb = M.n_bodies();
  auto need = [](const char* name, size_t got, int64_t want) {
    if (int64_t(got) != want)
      bad(std::string(name) + " must have " + std::to_string(want) + " entries (got " +
          std::to_string(got) + ")");
  };
  need("sigma_cr", in.sigma_cr.size(), P);
  need("tau_cr", in.tau_cr.size(), P);
  need("G", in.G.size(), P);
  for (auto* v : {&in.body_minus, &in.body_plus, &in.frame_p, &in.frame_q})
    need("pair arrays (body_minus, body_plus, frame_p, frame_q)", v->size(), K);
  for (auto* v : {&in.nx, &in.ny, &in.length})
    need("pair arrays (normal, length)", v->size(), K);
  if (P > 0 && K < P) bad("every bond point needs at least one pair");
  M.prepare_topology();
  std::vector<uint8_t> used(n, 0);
  for (int64_t p = 0; p < P; ++p) {
    const std::string where = "bond point " + std::to_string(p);
    const int32_t i = in.node[p];
    if (i < 0 || i >= n)
      bad(where + ": node must be in [0, " + std::to_string(n - 1) + "] (got " + std::to_string(i) + ")");
    if (used[i]) bad(where + ": node " + std::to_string(i) + " appears twice");
    used[i] = 1;
    if (!(in.sigma_cr[p] > 0.0) || !std::isfinite(in.sigma_cr[p]))
      bad(where + ": sigma_cr must be > 0 Pa and finite (got " + num(in.sigma_cr[p]) + ")");
    if (!(in.tau_cr[p] > 0.0) || !std::isfinite(in.tau_cr[p]))
      bad(where + ": tau_cr must be > 0 Pa and finite (got " + num(in.tau_cr[p]) + ")");
    if (!(in.G[p] > 0.0) || !std::isfinite(in.G[p]))
      bad(where + ": G must be > 0 J/m² and finite (got " + num(in.G[p]) + ")");
  }
  const BondHost& CM = M;
  const Nodes& N = CM.nodes();
  for (int64_t k = 0; k < K; ++k) {
    const std::string where = "bond pair " + std::to_string(k);
    const int32_t p = in.pair_point[k];
    if (p < 0 || p >= P) bad(where + ": point must be in [0, " + std::to_string(P - 1) + "]");
    if (k > 0 && p < in.pair_point[k - 1]) bad("pairs must be grouped by point (pair_point non-decreasing)");
    if (k > 0 && p > in.pair_point[k - 1] + 1) bad("bond point " + std::to_string(in.pair_point[k - 1] + 1) + " has no pair");
    if (k == 0 && p != 0) bad("bond point 0 has no pair");
    const int32_t i = in.node[p];
    const int32_t bm = in.body_minus[k], bp = in.body_plus[k];
    if (bm < 0 || bm >= nb || bp < 0 || bp >= nb || bm == bp)
      bad(where + ": body_minus and body_plus must be two different bodies in [0, " + std::to_string(nb - 1) + "]");
    if (!for_restore && (!M.node_touches_body(i, bm) || !M.node_touches_body(i, bp)))
      bad(where + ": bodies " + std::to_string(bm) + " and " + std::to_string(bp) +
          " must both have triangles at node " + std::to_string(i));
    const double nn = std::hypot(in.nx[k], in.ny[k]);
    if (!(nn > 0.0) || !std::isfinite(nn)) bad(where + ": normal must be finite and non-zero");
    if (!(in.length[k] > 0.0) || !std::isfinite(in.length[k]))
      bad(where + ": length l must be > 0 m and finite (got " + num(in.length[k]) + ")");
    const int32_t a = in.frame_p[k], b = in.frame_q[k];
    if (a < 0 || a >= n || b < 0 || b >= n || a == b)
      bad(where + ": frame_p and frame_q must be two different node ids in [0, " + std::to_string(n - 1) + "]");
    if (!(std::hypot(N.x0[b] - N.x0[a], N.y0[b] - N.y0[a]) > 0.0))
      bad(where + ": frame nodes " + std::to_string(a) + " and " + std::to_string(b) + " coincide");
  }
  if (K > 0 && in.pair_point[K - 1] != P - 1) bad("bond point " + std::to_string(P - 1) + " has no pair");

  // All valid: store.
  const BondParams keep = params_;
  *this = FreezeBonds{};
  params_ = keep;
  in_ = in;
  const size_t extent_size[] = {size_t(P), size_t(K), 0, 1};
  BondState::each(st_, [&](const char*, BondExtent e, auto& field, auto init) {
    if constexpr (is_bond_array<decltype(field)>)
      field.assign(extent_size[int(e)], init);
    else
      field = init;
  });
  beta_.resize(P);
  for (int64_t p = 0; p < P; ++p) beta_[p] = in_.tau_cr[p] / in_.sigma_cr[p];
  first_pair_.assign(P, 0);
  n_pairs_.assign(P, 0);
  for (int64_t k = K - 1; k >= 0; --k) {
    first_pair_[in.pair_point[k]] = int32_t(k);
    ++n_pairs_[in.pair_point[k]];
  }
  fail_.assign(P, 0);
  n0x_.resize(K);
  n0y_.resize(K);
  d0x_.resize(K);
  d0y_.resize(K);
  for (int64_t k = 0; k < K; ++k) {
    const double nn = std::hypot(in.nx[k], in.ny[k]);
    n0x_[k] = in.nx[k] / nn;
    n0y_[k] = in.ny[k] / nn;
    d0x_[k] = N.x0[in.frame_q[k]] - N.x0[in.frame_p[k]];
    d0y_[k] = N.y0[in.frame_q[k]] - N.y0[in.frame_p[k]];
  }
  tn_.assign(K, 0.0);
  tt_.assign(K, 0.0);
  refresh_lists();
}

void FreezeBonds::set_params(const BondParams& p) {
  if (!(std::isnan(p.mu) || (p.mu >= 0.0 && std::isfinite(p.mu))))
    bad("mu must be >= 0 and finite, or None to use the contact mu (got " + num(p.mu) + ")");
  if (p.screen_interval < 1)
    bad("screen_interval must be an integer >= 1 (1: no pre-screening) (got " +
        std::to_string(p.screen_interval) + ")");
  if (!(p.screen_fraction > 0.0 && p.screen_fraction < 1.0))
    bad("screen_fraction must be in (0, 1) (got " + num(p.screen_fraction) + ")");
  // Switching failure checking back on (or changing the screening) checks
  // every point at the next step, so no stale screening flag delays a failure.
  if (p.check_failure != params_.check_failure || p.screen_interval != params_.screen_interval ||
      p.screen_fraction != params_.screen_fraction)
    std::fill(st_.near.begin(), st_.near.end(), 1);
  params_ = p;
}

double FreezeBonds::mu(const BondHost& M) const {
  return std::isnan(params_.mu) ? M.contact_params().mu : params_.mu;
}

void FreezeBonds::refresh_lists() {
  intact_points_.clear();
  for (int32_t p = 0; p < n_points(); ++p)
    if (st_.point_state[p] == PointState::intact) intact_points_.push_back(p);
  open_pairs_.clear();
  closing_pairs_.clear();
  for (int32_t k = 0; k < n_pairs(); ++k) {
    if (st_.pair_state[k] == PairState::cohesive) open_pairs_.push_back(k);
    if (st_.pair_state[k] != PairState::intact) closing_pairs_.push_back(k);
  }
}

int32_t FreezeBonds::n_split() const {
  return int32_t(std::count(st_.point_state.begin(), st_.point_state.end(), PointState::split));
}

int32_t FreezeBonds::n_failed() const {
  return int32_t(std::count(st_.pair_state.begin(), st_.pair_state.end(), PairState::failed));
}

size_t FreezeBonds::memory_bytes() const {
  size_t b = 0;
  auto add = [&b](const auto& v) { b += v.capacity() * sizeof(v[0]); };
  auto add_field = [&](const char*, BondExtent, const auto& field, auto) {
    if constexpr (is_bond_array<decltype(field)>) add(field);
  };
  BondInput::each(in_, add_field);
  BondState::each(st_, add_field);
  for (auto* v : {&first_pair_, &n_pairs_, &intact_points_, &open_pairs_, &closing_pairs_}) add(*v);
  for (auto* v : {&beta_, &n0x_, &n0y_, &d0x_, &d0y_, &fx_pair_, &fy_pair_, &w_pair_, &s_pair_, &e_pair_,
                  &f_closure_})
    add(*v);
  add(tn_);
  add(tt_);
  add(fail_);
  return b;
}

// ---------------------------------------------------------------- eq 7 and the criterion

BondCheckArrays FreezeBonds::check_arrays(const BondHost& M) const {
  const Nodes& N = M.nodes();
  const Triangles& T = M.triangles();
  return {N.x.data(),         N.y.data(),         M.gather().start.data(), M.gather().slot.data(),
          T.stress.data(),    T.area0.data(),     in_.node.data(),         first_pair_.data(),
          n_pairs_.data(),    in_.sigma_cr.data(), in_.tau_cr.data(),      beta_.data(),
          in_.frame_p.data(), in_.frame_q.data(), d0x_.data(),             d0y_.data(),
          n0x_.data(),        n0y_.data(),        tn_.data(),              tt_.data()};
}

SplitPlan FreezeBonds::check(const BondHost& M) {
  SplitPlan plan;
  if (!params_.check_failure || intact_points_.empty()) return plan;
  const int64_t step = M.step_count();
  const int32_t k = params_.screen_interval;
  const double frac = params_.screen_fraction;
  const double mu = this->mu(M);
  const int32_t n = int32_t(intact_points_.size());
  const BondCheckArrays a = check_arrays(M);
  int64_t evaluated = 0;
  #pragma omp parallel for schedule(static) num_threads(team_size(M, n)) reduction(+ : evaluated)
  for (int32_t j = 0; j < n; ++j) {
    const int32_t p = intact_points_[j];
    if (k > 1 && !st_.near[p] && (step + p) % k != 0) {
      fail_[p] = 0;
      continue;
    }
    ++evaluated;
    const bool was_near = st_.near[p];
    const double r = bond_point_ratio(a, p, mu);
    st_.near[p] = r >= frac;
    fail_[p] = r >= 1.0 ? (was_near || k == 1 ? 1 : 2) : 0;
  }
  st_.checks += evaluated;
  for (int32_t j = 0; j < n; ++j) {
    const int32_t p = intact_points_[j];
    if (fail_[p]) {
      plan.points.push_back(p);
      if (fail_[p] == 2) ++st_.late_detections;  // found at a staggered check: up to k-1 steps late
    }
  }
  return plan;
}

void FreezeBonds::split(BondHost& M, const SplitPlan& plan) {
  if (plan.empty()) return;
  split_points(M, plan.points);
  refresh_lists();
}

// ---------------------------------------------------------------- eqs 9-11

CohesivePairArrays FreezeBonds::pair_arrays(const BondHost& M) const {
  const Nodes& N = M.nodes();
  return {N.x.data(),       N.y.data(),       N.vx.data(),         N.vy.data(),          N.mass.data(),
          N.f_x.data(),     N.f_y.data(),     N.f_con_x.data(),    N.f_con_y.data(),     in_.pair_point.data(),
          st_.node_plus.data(), st_.node_minus.data(), st_.fnx.data(), st_.fny.data(),    st_.f0.data(),
          st_.delta_f.data(), st_.delta_m.data(), st_.f_n_prev.data(), st_.f_t_prev.data(), st_.d_n_prev.data(),
          st_.d_t_prev.data(), beta_.data()};
}

// Eqs 9-11 on the opened pairs, then crack closure on the opened and failed
// ones. Crack closure: the crack faces of a bond point take part in contact
// (eqs 1-4) only once no node is shared between them any more: triangles
// that share a node never contact. Until the neighbouring bond points have
// split too, a closing crack would therefore interpenetrate freely, and when
// the last shared node splits the contact would meet a deep overlap at once
// and throw the faces apart (energy out of nothing). A node-to-node penalty
// on the split pair, as stiff as the contact penalty s (N/m per m, below the
// 6 s node stiffness of the potential contact the stable step allows for),
// keeps x+ and x- from crossing along the bond normal. It is conservative:
// its forces go with the contact forces, whose work the ledger books as
// stored contact energy.
void FreezeBonds::apply(BondHost& M, bool commit) {
  const int32_t n = int32_t(open_pairs_.size()), nc = int32_t(closing_pairs_.size());
  // every entry is written below
  fx_pair_.resize(n);
  fy_pair_.resize(n);
  w_pair_.resize(n);
  s_pair_.resize(n);
  e_pair_.resize(n);
  f_closure_.resize(nc);
  const CohesivePairArrays a = pair_arrays(M);
  const CohesiveHistory h{st_.delta_m.data(), st_.f_n_prev.data(), st_.f_t_prev.data(), st_.d_n_prev.data(),
                          st_.d_t_prev.data(), st_.pair_state.data(), st_.mode.data(), st_.t_fail.data(),
                          st_.x_fail.data(), st_.y_fail.data(), st_.dn_fail.data(), st_.dt_fail.data()};
  const cl::ForceDirection dir = params_.direction;
  const double time = M.time();
  const double dt = M.dt();
  const double k_closure = M.contact_params().penalty;
  Nodes& W = M.bond_nodes();
  const int32_t n_nodes = W.size();
  bool any_failed = false;
  #pragma omp parallel num_threads(team_size(M, std::max(n, nc)))
  {
    #pragma omp for schedule(static) reduction(|| : any_failed) nowait
    for (int32_t j = 0; j < n; ++j) {
      const int32_t k = open_pairs_[j];
      const CohesivePairStep r = cohesive_pair_step(a, k, dir, dt);
      fx_pair_[j] = r.fpx;
      fy_pair_[j] = r.fpy;
      w_pair_[j] = r.work;
      s_pair_[j] = r.stored;
      e_pair_[j] = r.dissipation;
      if (commit && commit_pair_step(h, a, k, r, time)) any_failed = true;
    }
    // crack closure's forces (above): positions only
    #pragma omp for schedule(static)
    for (int32_t c = 0; c < nc; ++c) {
      const int32_t k = closing_pairs_[c];
      double f;
      f_closure_[c] = crack_closure_force(W.x.data(), W.y.data(), st_.node_plus[k], st_.node_minus[k], st_.fnx[k],
                                          st_.fny[k], k_closure, f) ? f : kNoClosure;
    }
    // Scatter: each thread adds onto its own block of nodes, visiting every
    // pair in order, so each node takes its terms in pair order: one
    // thread's bits, whatever the count (the serial scatter was most of the
    // bonds part on two threads).
    const int tid = omp_get_thread_num(), team = omp_get_num_threads();
    int32_t lo, hi;
    block(n_nodes, tid, team, lo, hi);
    const auto mine = [lo, hi](int32_t i) { return i >= lo && i < hi; };
    for (int32_t j = 0; j < n; ++j) {
      const int32_t k = open_pairs_[j], ip = st_.node_plus[k], im = st_.node_minus[k];
      if (mine(ip)) {
        W.f_coh_x[ip] += fx_pair_[j];
        W.f_coh_y[ip] += fy_pair_[j];
      }
      if (mine(im)) {
        W.f_coh_x[im] -= fx_pair_[j];
        W.f_coh_y[im] -= fy_pair_[j];
      }
    }
    for (int32_t c = 0; c < nc; ++c) {
      const double f = f_closure_[c];
      if (f == kNoClosure) continue;
      const int32_t k = closing_pairs_[c], ip = st_.node_plus[k], im = st_.node_minus[k];
      const double nx = st_.fnx[k], ny = st_.fny[k];  // pushes x+ along +n and x- along -n
      if (mine(ip)) {
        W.f_con_x[ip] += f * nx;
        W.f_con_y[ip] += f * ny;
      }
      if (mine(im)) {
        W.f_con_x[im] -= f * nx;
        W.f_con_y[im] -= f * ny;
      }
    }
  }
  if (!commit) return;
  double work = 0.0, stored = 0.0, eff = 0.0;
  for (int32_t j = 0; j < n; ++j) {
    work += w_pair_[j];
    stored += s_pair_[j];
    eff += e_pair_[j];
  }
  st_.work += work;
  st_.stored = stored;
  st_.dissipation_effective += eff;
  if (any_failed) refresh_lists();
}

// ---------------------------------------------------------------- checkpoints

void FreezeBonds::restore(BondHost& M, const BondState& s) {
  const size_t extent_size[] = {in_.node.size(), in_.pair_point.size(), 0, 1};
  BondState::each(s, [&](const char* name, BondExtent e, const auto& field, auto) {
    if constexpr (is_bond_array<decltype(field)>) {
      if (e != BondExtent::split_node && field.size() != extent_size[int(e)])
        bad(std::string("bond state: ") + name + " must have " + std::to_string(extent_size[int(e)]) +
            " entries (got " + std::to_string(field.size()) + "); set the same bond points first");
    }
  });
  M.prepare_topology();
  const int32_t n = M.nodes().size();
  if (s.parent.size() > size_t(n)) bad("bond state: more split nodes than model nodes");
  for (size_t k = 0; k < in_.pair_point.size(); ++k) {
    if (s.pair_state[k] == PairState::intact) continue;
    const int32_t a = s.node_plus[k], b = s.node_minus[k];
    if (a < 0 || a >= n || b < 0 || b >= n || !M.node_touches_body(a, in_.body_plus[k]) ||
        !M.node_touches_body(b, in_.body_minus[k]))
      bad("bond state: pair " + std::to_string(k) +
          " does not match the model's split topology (build the model from the checkpoint's "
          "nodes and triangles)");
  }
  st_ = s;
  fail_.assign(in_.node.size(), 0);
  refresh_lists();
}

}  // namespace engine
