// The sleeping far field (sleeping.hpp): its parameters, the body balance
// window, state for checkpoints and the list of triangles a step computes.
#include "common/input_errors.hpp"
#include "common/parameter_range.hpp"
#include "engine_parameter_ranges.hpp"
#include "model/model.hpp"

#include <algorithm>
#include <cmath>

namespace engine {

void validate(const SleepParams& p) {
  check(registry::sleep_velocity, p.velocity);
  check(registry::sleep_force, p.force);
  check(registry::sleep_quiet_steps, double(p.quiet_steps));
}

void Model::wake_all() {
  std::fill(nodes_.sleep.begin(), nodes_.sleep.end(), uint8_t(0));
  std::fill(nodes_.quiet.begin(), nodes_.quiet.end(), 0);
  std::fill(body_wake_.begin(), body_wake_.end(), uint8_t(0));
  window_.start_step = -1;
  awake_current_ = false;
}

void Model::restore_sleep_state(const SleepState& s) {
  const size_t n = size_t(nodes_.size());
  if (s.sleep.size() != n || s.quiet.size() != n || s.f_ref_x.size() != n || s.f_ref_y.size() != n)
    bad("sleep state must have one entry per node (" + std::to_string(n) + "): sleep has " +
        std::to_string(s.sleep.size()) + ", quiet " + std::to_string(s.quiet.size()) + ", f_ref_x " +
        std::to_string(s.f_ref_x.size()) + ", f_ref_y " + std::to_string(s.f_ref_y.size()));
  for (size_t i = 0; i < n; ++i) {
    if (s.sleep[i] > 2) bad("sleep state of a node must be 0, 1 or 2 (node " + std::to_string(i) + ")");
    if (s.quiet[i] < 0) bad("quiet step count of a node must be >= 0 (node " + std::to_string(i) + ")");
  }
  const SleepWindow& w = s.window;
  const size_t B = size_t(n_bodies());
  if (w.start_step >= 0 && (w.cx.size() != B || w.cy.size() != B || w.px.size() != B || w.py.size() != B ||
                            w.l.size() != B))
    bad("sleep window must have one entry per body (" + std::to_string(B) + "): window_cx has " +
        std::to_string(w.cx.size()) + ", window_cy " + std::to_string(w.cy.size()) + ", window_px " +
        std::to_string(w.px.size()) + ", window_py " + std::to_string(w.py.size()) + ", window_l " +
        std::to_string(w.l.size()));
  nodes_.sleep = s.sleep;
  nodes_.quiet = s.quiet;
  nodes_.f_ref_x = s.f_ref_x;
  nodes_.f_ref_y = s.f_ref_y;
  window_ = w;
  window_.n_nodes = nodes_.size();
  body_wake_.assign(B, 0);
  awake_current_ = false;
  compute_all_next_ = true;
}

SleepState Model::sleep_state() const {
  return SleepState{nodes_.sleep, nodes_.quiet, nodes_.f_ref_x, nodes_.f_ref_y, window_};
}

int32_t Model::asleep_nodes() const {
  return int32_t(std::count_if(nodes_.sleep.begin(), nodes_.sleep.end(), [](uint8_t s) { return s != 0; }));
}

int32_t Model::awake_triangles() {
  if (!params_.sleep.on) return tris_.size();
  rebuild_awake_triangles();
  return int32_t(awake_tris_.size());
}

// A triangle whose corners have all been asleep since before the last update
// was computed at its frozen place already: its stored forces are exact.
void Model::rebuild_awake_triangles() {
  if (awake_current_) return;
  awake_tris_.clear();
  const uint8_t* s = nodes_.sleep.data();
  const int32_t* v = tris_.node.data();
  for (int32_t t = 0; t < tris_.size(); ++t)
    if (s[v[3 * t]] < 2 || s[v[3 * t + 1]] < 2 || s[v[3 * t + 2]] < 2) awake_tris_.push_back(t);
  awake_current_ = true;
}

// Each body's momentum and angular momentum about (cx, cy) [per body], with
// the inertial masses the update uses (its momentum change is then exactly
// the sum of the forces on the body's nodes times dt).
void Model::body_momenta(const std::vector<double>& cx, const std::vector<double>& cy, std::vector<double>& px,
                         std::vector<double>& py, std::vector<double>& l) const {
  const Nodes& N = nodes_;
  const size_t B = size_t(n_bodies());
  px.assign(B, 0.0);
  py.assign(B, 0.0);
  l.assign(B, 0.0);
  for (int32_t i = 0; i < N.size(); ++i) {
    const int32_t b = node_body_[i];
    const double qx = N.mass[i] * N.vx[i], qy = N.mass[i] * N.vy[i];
    px[b] += qx;
    py[b] += qy;
    l[b] += (N.x[i] - cx[b]) * qy - (N.y[i] - cy[b]) * qx;
  }
}

void Model::open_sleep_window() {
  const Nodes& N = nodes_;
  const size_t B = size_t(n_bodies());
  std::vector<double> w(B, 0.0);
  window_.cx.assign(B, 0.0);
  window_.cy.assign(B, 0.0);
  for (int32_t i = 0; i < N.size(); ++i) {
    const int32_t b = node_body_[i];
    w[b] += N.mass_phys[i];
    window_.cx[b] += N.mass_phys[i] * N.x[i];
    window_.cy[b] += N.mass_phys[i] * N.y[i];
  }
  for (size_t b = 0; b < B; ++b)
    if (w[b] > 0.0) {
      window_.cx[b] /= w[b];
      window_.cy[b] /= w[b];
    }
  body_momenta(window_.cx, window_.cy, window_.px, window_.py, window_.l);
  window_.start_step = step_count_;
  window_.start_time = time_;
  window_.n_nodes = nodes_.size();
}

// After each update with sleeping on: wake the bodies a node woke, then, at
// the end of a window, put to sleep the bodies at rest in it (sleeping.hpp).
void Model::update_sleep() {
  Nodes& N = nodes_;
  const size_t B = size_t(n_bodies());
  if (body_wake_.size() != B) body_wake_.assign(B, 0);
  if (std::find(body_wake_.begin(), body_wake_.end(), uint8_t(1)) != body_wake_.end()) {
    for (int32_t i = 0; i < N.size(); ++i)
      if (N.sleep[i] && body_wake_[node_body_[i]]) {
        N.sleep[i] = 0;
        N.quiet[i] = 0;
      }
    std::fill(body_wake_.begin(), body_wake_.end(), uint8_t(0));
    awake_current_ = false;
  }
  if (window_.start_step < 0 || window_.n_nodes != N.size()) {
    open_sleep_window();
    return;
  }
  if (step_count_ - window_.start_step < params_.sleep.quiet_steps) return;
  const double T = time_ - window_.start_time;
  const double g = params_.external.g;  // the sleep force is a fraction of the weight at the set g, also with gravity off
  std::vector<double> weight(B, 0.0);
  std::vector<uint8_t> still(B, 1);
  for (int32_t i = 0; i < N.size(); ++i) {
    const int32_t b = node_body_[i];
    weight[b] += N.mass_phys[i] * g;
    // a body with a held or driven node is loaded through it: never asleep
    if (N.constrained[i] || N.sleep[i] || N.quiet[i] < params_.sleep.quiet_steps) still[b] = 0;
  }
  std::vector<double> px, py, l;
  body_momenta(window_.cx, window_.cy, px, py, l);
  std::vector<uint8_t> falls(B, 0);
  bool any = false;
  for (size_t b = 0; b < B; ++b) {
    if (!still[b] || !(T > 0.0)) continue;
    const double fmax = params_.sleep.force * weight[b];
    const double f = std::hypot(px[b] - window_.px[b], py[b] - window_.py[b]) / T;
    const double moment = std::fabs(l[b] - window_.l[b]) / T;
    if (f < fmax && moment < fmax * std::sqrt(body_area0_[b])) {
      falls[b] = 1;
      any = true;
    }
  }
  if (any) {
    double lost = 0.0, shift = 0.0;
    for (int32_t i = 0; i < N.size(); ++i) {
      if (!falls[node_body_[i]]) continue;
      lost += 0.5 * N.mass[i] * (N.vx[i] * N.vx[i] + N.vy[i] * N.vy[i]);
      shift += rescale_velocity(i, 0.0);
      N.vx[i] = N.vy[i] = 0.0;   // exactly
      N.sleep[i] = 1;
    }
    // that kinetic energy is taken out: booked as damping, the ledger still closes
    energy_.kinetic -= lost;
    energy_.damping += lost + shift;
    awake_current_ = false;
  }
  open_sleep_window();
}

}  // namespace engine
