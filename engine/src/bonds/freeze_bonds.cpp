#include "common/input_errors.hpp"
#include "bonds/freeze_bonds.hpp"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "cohesive_law/criterion.hpp"
#include "model/model.hpp"

namespace engine {

namespace cl = cohesive_law;

namespace {

// Below this many points (pairs) a pass is a few microseconds and a thread
// team costs more than it saves.
constexpr int32_t kMinParallelItems = 1024;

// Rigid phase of an opened pair. Eq 11 has no usable direction while the
// opening is round-off (just split, both nodes at one place), and at a small
// opening delta_e its direction turns with a stiffness |f_c| c/delta_e
// (c = beta for 'paper', beta^2 for 'work_conjugate') that the explicit step
// cannot integrate once it exceeds m_r/dt² (m_r: reduced mass of the two
// nodes): the pair would chatter. So until delta_m has once exceeded
//   delta_r = max(kRigidOpening delta_f, 4 |f0| max(1, c) dt²/m_r)
// the pair acts as a constraint: it holds the nodes together with the
// eq-8 force of the step when that force's effective value is within the
// law's |f_c| = f0 (1 - delta_m/delta_f), and otherwise pulls with |f_c| along
// it (so the crack opens in the direction the elements drive it). Past
// delta_r eq 11 takes over with a direction that is stable to integrate (the
// factor 4 keeps k dt²/m_r <= 1/4, so with an element mode at 0.9 of its
// limit, (w dt)² <= 3.24, the sum stays below 4).
// delta_m, |f_c| and the dissipation follow eq 10 throughout.
constexpr double kRigidOpening = 1e-6;

struct Timer {
  explicit Timer(double& acc) : acc_(acc), t0_(omp_get_wtime()) {}
  ~Timer() { acc_ += omp_get_wtime() - t0_; }
  double& acc_;
  double t0_;
};

}  // namespace

// ---------------------------------------------------------------- setup

int FreezeBonds::team_size(const Model& M, int64_t items) {
  if (items < kMinParallelItems) return 1;
  const int t = M.threads_ > 0 ? M.threads_ : omp_get_max_threads();
  return std::max(1, t);
}

void FreezeBonds::clear() {
  *this = FreezeBonds{};
}

void FreezeBonds::set(Model& M, const BondInput& in, bool for_restore) {
  if (!parent_.empty())
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
  const Nodes& N = M.nodes();
  const Triangles& T = M.triangles();
  auto body_at = [&](int32_t node, int32_t b) {
    for (int32_t j = M.gather_.start[node]; j < M.gather_.start[node + 1]; ++j)
      if (T.body[M.gather_.slot[j] / 3] == b) return true;
    return false;
  };
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
    if (!for_restore && (!body_at(i, bm) || !body_at(i, bp)))
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
  input_ = in;
  node_ = in.node;
  sigma_ = in.sigma_cr;
  tau_ = in.tau_cr;
  G_ = in.G;
  beta_.resize(P);
  for (int64_t p = 0; p < P; ++p) beta_[p] = tau_[p] / sigma_[p];
  first_pair_.assign(P, 0);
  n_pairs_.assign(P, 0);
  for (int64_t k = K - 1; k >= 0; --k) {
    first_pair_[in.pair_point[k]] = int32_t(k);
    ++n_pairs_[in.pair_point[k]];
  }
  point_state_.assign(P, 0);
  near_.assign(P, 1);  // everything is checked on the first step
  fail_.assign(P, 0);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  t_split_.assign(P, nan);
  x_split_.assign(P, nan);
  y_split_.assign(P, nan);
  pair_point_ = in.pair_point;
  body_minus_ = in.body_minus;
  body_plus_ = in.body_plus;
  frame_p_ = in.frame_p;
  frame_q_ = in.frame_q;
  l_ = in.length;
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
  pair_state_.assign(K, 0);
  node_plus_.assign(K, -1);
  node_minus_.assign(K, -1);
  for (auto* v : {&fnx_, &fny_, &f0_, &delta_f_, &delta_m_, &f_n_prev_, &f_t_prev_, &d_n_prev_,
                  &d_t_prev_})
    v->assign(K, 0.0);
  for (auto* v : {&split_tn_, &split_tt_, &t_fail_, &x_fail_, &y_fail_, &dn_fail_, &dt_fail_})
    v->assign(K, nan);
  mode_.assign(K, 0);
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
    std::fill(near_.begin(), near_.end(), 1);
  params_ = p;
}

double FreezeBonds::mu(const Model& M) const {
  return std::isnan(params_.mu) ? M.contact_params().mu : params_.mu;
}

void FreezeBonds::refresh_lists() {
  intact_points_.clear();
  for (int32_t p = 0; p < n_points(); ++p)
    if (point_state_[p] == 0) intact_points_.push_back(p);
  open_pairs_.clear();
  for (int32_t k = 0; k < n_pairs(); ++k)
    if (pair_state_[k] == 1) open_pairs_.push_back(k);
}

int32_t FreezeBonds::n_split() const {
  return int32_t(std::count(point_state_.begin(), point_state_.end(), int8_t(1)));
}

int32_t FreezeBonds::n_failed() const {
  return int32_t(std::count(pair_state_.begin(), pair_state_.end(), int8_t(2)));
}

size_t FreezeBonds::memory_bytes() const {
  size_t b = 0;
  auto add = [&b](const auto& v) { b += v.capacity() * sizeof(v[0]); };
  for (auto* v : {&node_, &first_pair_, &n_pairs_, &pair_point_, &body_minus_, &body_plus_,
                  &frame_p_, &frame_q_, &node_plus_, &node_minus_, &intact_points_,
                  &open_pairs_, &parent_})
    add(*v);
  for (auto* v : {&sigma_, &tau_, &G_, &beta_, &t_split_, &x_split_, &y_split_, &n0x_, &n0y_,
                  &d0x_, &d0y_, &l_, &tn_, &tt_, &fnx_, &fny_, &f0_, &delta_f_, &delta_m_,
                  &f_n_prev_, &f_t_prev_, &d_n_prev_, &d_t_prev_, &split_tn_, &split_tt_,
                  &t_fail_, &x_fail_, &y_fail_, &dn_fail_, &dt_fail_, &fx_pair_, &fy_pair_,
                  &w_pair_, &s_pair_, &e_pair_})
    add(*v);
  for (auto* v : {&point_state_, &near_, &fail_, &pair_state_, &mode_}) add(*v);
  return b;
}

// ---------------------------------------------------------------- eq 7 and the criterion

void FreezeBonds::mean_stress(const Model& M, int32_t node, double& sxx, double& syy,
                              double& sxy) const {
  const int32_t* start = M.gather_.start.data();
  const int32_t* slot = M.gather_.slot.data();
  const double* sig = M.tris_.stress.data();
  const double* A = M.tris_.area0.data();
  double a = 0.0, xx = 0.0, yy = 0.0, xy = 0.0;
  for (int32_t j = start[node]; j < start[node + 1]; ++j) {
    const int32_t t = slot[j] / 3;
    const double w = A[t];
    a += w;
    xx += w * sig[3 * t];
    yy += w * sig[3 * t + 1];
    xy += w * sig[3 * t + 2];
  }
  sxx = xx / a;
  syy = yy / a;
  sxy = xy / a;
}

void FreezeBonds::current_normal(const Model& M, int32_t k, double& nx, double& ny) const {
  const Nodes& N = M.nodes_;
  const double dx = N.x[frame_q_[k]] - N.x[frame_p_[k]];
  const double dy = N.y[frame_q_[k]] - N.y[frame_p_[k]];
  // rotation from the reference frame edge d0 to its current direction d
  double c = d0x_[k] * dx + d0y_[k] * dy;
  double s = d0x_[k] * dy - d0y_[k] * dx;
  const double r = 1.0 / std::sqrt(c * c + s * s);  // |d0| |d|, never 0 for a valid mesh
  c *= r;
  s *= r;
  nx = c * n0x_[k] - s * n0y_[k];
  ny = s * n0x_[k] + c * n0y_[k];
}

double FreezeBonds::point_ratio(const Model& M, int32_t p, double mu) {
  double sxx, syy, sxy;
  mean_stress(M, node_[p], sxx, syy, sxy);
  double worst = -std::numeric_limits<double>::infinity();
  bool reached = false;
  for (int32_t k = first_pair_[p]; k < first_pair_[p] + n_pairs_[p]; ++k) {
    double nx, ny;
    current_normal(M, k, nx, ny);
    // eq 7: t = sigma n; normal and tangential (t = (-n_y, n_x)) parts
    const double tx = sxx * nx + sxy * ny, ty = sxy * nx + syy * ny;
    const double t_n = tx * nx + ty * ny, t_t = -tx * ny + ty * nx;
    tn_[k] = t_n;
    tt_[k] = t_t;
    reached = reached || cl::criterion_reached(t_n, t_t, sigma_[p], tau_[p], mu);
    worst = std::max(worst, cl::effective_traction(t_n, t_t, beta_[p], mu) / sigma_[p]);
  }
  // The split decision is eq 5 itself; the ratio only steers the screening.
  return reached ? std::max(worst, 1.0) : std::min(worst, std::nextafter(1.0, 0.0));
}

void FreezeBonds::check(Model& M) {
  in_step_ = true;
  if (!params_.check_failure || intact_points_.empty()) return;
  Timer timer(M.timings_.bonds);
  const int64_t step = M.step_count();
  const int32_t k = params_.screen_interval;
  const double frac = params_.screen_fraction;
  const double mu = this->mu(M);
  const int32_t n = int32_t(intact_points_.size());
  int64_t evaluated = 0;
  #pragma omp parallel for schedule(static) num_threads(team_size(M, n)) reduction(+ : evaluated)
  for (int32_t j = 0; j < n; ++j) {
    const int32_t p = intact_points_[j];
    if (k > 1 && !near_[p] && (step + p) % k != 0) {
      fail_[p] = 0;
      continue;
    }
    ++evaluated;
    const bool was_near = near_[p];
    const double r = point_ratio(M, p, mu);
    near_[p] = r >= frac;
    fail_[p] = r >= 1.0 ? (was_near || k == 1 ? 1 : 2) : 0;
  }
  checks_ += evaluated;
  std::vector<int32_t> failing;
  for (int32_t j = 0; j < n; ++j) {
    const int32_t p = intact_points_[j];
    if (fail_[p]) {
      failing.push_back(p);
      if (fail_[p] == 2) ++late_;  // found at a staggered check: up to k-1 steps late
    }
  }
  if (!failing.empty()) {
    split_points(M, failing);
    refresh_lists();
  }
}

// ---------------------------------------------------------------- eqs 9-11

void FreezeBonds::apply(Model& M) {
  const bool update = in_step_;  // evaluate() only looks: no history changes
  in_step_ = false;
  Timer timer(M.timings_.bonds);
  const int32_t n = int32_t(open_pairs_.size());
  fx_pair_.assign(n, 0.0);
  fy_pair_.assign(n, 0.0);
  w_pair_.assign(n, 0.0);
  s_pair_.assign(n, 0.0);
  e_pair_.assign(n, 0.0);
  const Nodes& N = M.nodes_;
  const cl::ForceDirection dir = params_.direction;
  const double time = M.time();
  const double dt2 = M.dt() * M.dt();
  bool any_failed = false;
  #pragma omp parallel for schedule(static) num_threads(team_size(M, n)) reduction(|| : any_failed)
  for (int32_t j = 0; j < n; ++j) {
    const int32_t k = open_pairs_[j];
    const int32_t p = pair_point_[k];
    const double beta = beta_[p];
    const int32_t ip = node_plus_[k], im = node_minus_[k];
    const double nx = fnx_[k], ny = fny_[k];
    double dn, dt;
    cl::opening_components(N.x[ip] - N.x[im], N.y[ip] - N.y[im], nx, ny, dn, dt);
    double dm = delta_m_[k];
    double fn = 0.0, ft = 0.0;  // the law's force, along the opening (bond axes)
    bool failed = false;
    cl::FailureMode mode = cl::FailureMode::none;
    // dm < delta_r without a division: dm m+ m- < 4 f0 max(1, c) dt² (m+ + m-)
    const double mp = N.mass[ip], mm = N.mass[im];
    const double c = dir == cl::ForceDirection::paper ? beta : beta * beta;
    const bool rigid = dm < kRigidOpening * delta_f_[k] ||
                       dm * mp * mm < 4.0 * f0_[k] * std::max(1.0, c) * dt2 * (mp + mm);
    if (rigid) {
      const cl::StepOutcome s = cl::step_opened_bond(dn, dt, beta, f0_[k], delta_f_[k], dm, dir);
      failed = s.failed_now;
      mode = s.mode;
      if (!failed) {
        double gx, gy;
        split_force(M, k, false, gx, gy);
        const double gn = gx * nx + gy * ny, gt = -gx * ny + gy * nx;
        const double F = f0_[k] * (1.0 - dm / delta_f_[k]);
        const double geff = cl::initial_effective_force(gn, gt, beta, dir);
        const double scale = geff > F ? F / geff : 1.0;
        fn = -scale * gn;
        ft = -scale * gt;
      }
    } else {
      const cl::StepOutcome s = cl::step_opened_bond(dn, dt, beta, f0_[k], delta_f_[k], dm, dir);
      failed = s.failed_now;
      mode = s.mode;
      fn = s.f_n;
      ft = s.f_t;
    }
    double fpx, fpy, fmx, fmy;
    cl::nodal_forces(fn, ft, nx, ny, fpx, fpy, fmx, fmy);
    fx_pair_[j] = fpx;
    fy_pair_[j] = fpy;
    w_pair_[j] = cl::work_increment(f_n_prev_[k], f_t_prev_[k], fn, ft, dn - d_n_prev_[k],
                                    dt - d_t_prev_[k]);
    s_pair_[j] = cl::stored_energy(dn, dt, beta, f0_[k], delta_f_[k], dm, dir);
    e_pair_[j] = cl::dissipation_increment(f0_[k], delta_f_[k], delta_m_[k], dm);
    if (update) {
      delta_m_[k] = dm;
      f_n_prev_[k] = fn;
      f_t_prev_[k] = ft;
      d_n_prev_[k] = dn;
      d_t_prev_[k] = dt;
      if (failed) {
        pair_state_[k] = 2;
        t_fail_[k] = time;
        x_fail_[k] = 0.5 * (N.x[ip] + N.x[im]);
        y_fail_[k] = 0.5 * (N.y[ip] + N.y[im]);
        dn_fail_[k] = dn;
        dt_fail_[k] = dt;
        mode_[k] = int8_t(mode);
        any_failed = true;
      }
    }
  }
  // Scatter in pair order: deterministic, whatever the thread count.
  Nodes& W = M.nodes_;
  double work = 0.0, stored = 0.0, eff = 0.0;
  for (int32_t j = 0; j < n; ++j) {
    const int32_t k = open_pairs_[j];
    W.f_coh_x[node_plus_[k]] += fx_pair_[j];
    W.f_coh_y[node_plus_[k]] += fy_pair_[j];
    W.f_coh_x[node_minus_[k]] -= fx_pair_[j];
    W.f_coh_y[node_minus_[k]] -= fy_pair_[j];
    work += w_pair_[j];
    stored += s_pair_[j];
    eff += e_pair_[j];
  }
  apply_crack_closure(M);
  if (!update) return;
  work_ += work;
  stored_ = stored;
  dissipation_eff_ += eff;
  // The ledger's cohesive term is the work done against the cohesive forces
  // (booked by Model::update_positions); the part stored on the secant
  // branches is recoverable, so it moves from "dissipated" to "stored".
  EnergyLedger& E = M.energy_;
  E.cohesive -= stored - E.cohesive_stored;
  E.cohesive_stored = stored;
  if (any_failed) refresh_lists();
}

// ---------------------------------------------------------------- crack closure

// The crack faces of a bond point take part in contact (eqs 1-4) only once no
// node is shared between them any more: triangles that share a node never
// contact. Until the neighbouring bond points have split too, a closing crack
// would therefore interpenetrate freely, and when the last shared node splits
// the contact would meet a deep overlap at once and throw the faces apart
// (energy out of nothing). A node-to-node penalty on the split pair, as stiff
// as the contact penalty s (N/m per m, below the 6 s node stiffness of the
// potential contact the stable step allows for), keeps x+ and x- from
// crossing along the bond normal. It is conservative: its forces go with the
// contact forces, whose work the ledger books as stored contact energy.
void FreezeBonds::apply_crack_closure(Model& M) {
  const double k = M.contact_params().penalty;
  Nodes& W = M.nodes_;
  const int32_t n = int32_t(pair_state_.size());
  for (int32_t j = 0; j < n; ++j) {
    if (pair_state_[j] == 0) continue;
    const int32_t ip = node_plus_[j], im = node_minus_[j];
    const double nx = fnx_[j], ny = fny_[j];
    const double dn = (W.x[ip] - W.x[im]) * nx + (W.y[ip] - W.y[im]) * ny;
    if (dn >= 0.0) continue;
    const double f = -k * dn;  // pushes x+ along +n and x- along -n
    W.f_con_x[ip] += f * nx;
    W.f_con_y[ip] += f * ny;
    W.f_con_x[im] -= f * nx;
    W.f_con_y[im] -= f * ny;
  }
}

// ---------------------------------------------------------------- checkpoints

BondState FreezeBonds::state(const Model& M) const {
  BondState s;
  s.time = M.time();
  s.step_count = M.step_count();
  s.point_state = point_state_;
  s.near = near_;
  s.t_split = t_split_;
  s.x_split = x_split_;
  s.y_split = y_split_;
  s.pair_state = pair_state_;
  s.node_plus = node_plus_;
  s.node_minus = node_minus_;
  s.fnx = fnx_;
  s.fny = fny_;
  s.f0 = f0_;
  s.delta_f = delta_f_;
  s.delta_m = delta_m_;
  s.f_n_prev = f_n_prev_;
  s.f_t_prev = f_t_prev_;
  s.d_n_prev = d_n_prev_;
  s.d_t_prev = d_t_prev_;
  s.split_tn = split_tn_;
  s.split_tt = split_tt_;
  s.t_fail = t_fail_;
  s.x_fail = x_fail_;
  s.y_fail = y_fail_;
  s.dn_fail = dn_fail_;
  s.dt_fail = dt_fail_;
  s.mode = mode_;
  s.parent = parent_;
  s.work = work_;
  s.dissipation_effective = dissipation_eff_;
  s.stored = stored_;
  s.late_detections = late_;
  s.checks = checks_;
  return s;
}

void FreezeBonds::restore(Model& M, const BondState& s) {
  const size_t P = node_.size(), K = pair_point_.size();
  auto need = [](const char* name, size_t got, size_t want) {
    if (got != want)
      bad(std::string("bond state: ") + name + " must have " + std::to_string(want) +
          " entries (got " + std::to_string(got) + "); set the same bond points first");
  };
  for (auto* v : {&s.point_state, &s.near}) need("point_state/near", v->size(), P);
  for (auto* v : {&s.t_split, &s.x_split, &s.y_split}) need("t_split/x_split/y_split", v->size(), P);
  for (auto* v : {&s.pair_state, &s.mode}) need("pair_state/mode", v->size(), K);
  for (auto* v : {&s.node_plus, &s.node_minus}) need("node_plus/node_minus", v->size(), K);
  for (auto* v : {&s.fnx, &s.fny, &s.f0, &s.delta_f, &s.delta_m, &s.f_n_prev, &s.f_t_prev,
                  &s.d_n_prev, &s.d_t_prev, &s.split_tn, &s.split_tt, &s.t_fail, &s.x_fail,
                  &s.y_fail, &s.dn_fail, &s.dt_fail})
    need("pair arrays", v->size(), K);
  M.prepare_topology();
  const int32_t n = M.nodes().size();
  if (s.parent.size() > size_t(n)) bad("bond state: more split nodes than model nodes");
  const Triangles& T = M.triangles();
  auto body_at = [&](int32_t node, int32_t b) {
    for (int32_t j = M.gather_.start[node]; j < M.gather_.start[node + 1]; ++j)
      if (T.body[M.gather_.slot[j] / 3] == b) return true;
    return false;
  };
  for (size_t k = 0; k < K; ++k) {
    if (s.pair_state[k] == 0) continue;
    const int32_t a = s.node_plus[k], b = s.node_minus[k];
    if (a < 0 || a >= n || b < 0 || b >= n || !body_at(a, body_plus_[k]) || !body_at(b, body_minus_[k]))
      bad("bond state: pair " + std::to_string(k) +
          " does not match the model's split topology (build the model from the checkpoint's "
          "nodes and triangles)");
  }
  point_state_ = s.point_state;
  near_ = s.near;
  t_split_ = s.t_split;
  x_split_ = s.x_split;
  y_split_ = s.y_split;
  pair_state_ = s.pair_state;
  node_plus_ = s.node_plus;
  node_minus_ = s.node_minus;
  fnx_ = s.fnx;
  fny_ = s.fny;
  f0_ = s.f0;
  delta_f_ = s.delta_f;
  delta_m_ = s.delta_m;
  f_n_prev_ = s.f_n_prev;
  f_t_prev_ = s.f_t_prev;
  d_n_prev_ = s.d_n_prev;
  d_t_prev_ = s.d_t_prev;
  split_tn_ = s.split_tn;
  split_tt_ = s.split_tt;
  t_fail_ = s.t_fail;
  x_fail_ = s.x_fail;
  y_fail_ = s.y_fail;
  dn_fail_ = s.dn_fail;
  dt_fail_ = s.dt_fail;
  mode_ = s.mode;
  parent_ = s.parent;
  work_ = s.work;
  dissipation_eff_ = s.dissipation_effective;
  stored_ = s.stored;
  late_ = s.late_detections;
  checks_ = s.checks;
  fail_.assign(P, 0);
  refresh_lists();
  M.time_ = s.time;
  M.step_count_ = s.step_count;
}

}  // namespace engine
