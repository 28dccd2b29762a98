// The sleeping far field (sleeping.hpp): its parameters, state and the list
// of triangles a step computes.
#include "common/input_errors.hpp"
#include "model/model.hpp"

#include <algorithm>
#include <cmath>

namespace engine {

void Model::set_sleeping(bool on, double velocity, double force, int32_t quiet_steps) {
  if (!(velocity >= 0.0) || !std::isfinite(velocity))
    bad("sleep_velocity must be >= 0 m/s and finite (got " + num(velocity) + ")");
  if (!(force >= 0.0) || !std::isfinite(force))
    bad("sleep_force must be >= 0 (a fraction of the node's weight) and finite (got " + num(force) + ")");
  if (quiet_steps < 1) bad("sleep_quiet_steps must be >= 1 (got " + std::to_string(quiet_steps) + ")");
  const bool switched = on != sleep_.on;
  sleep_ = SleepParams{on, velocity, force, quiet_steps};
  if (switched) wake_all();  // new thresholds apply to the nodes as they are
}

void Model::wake_all() {
  std::fill(nodes_.sleep.begin(), nodes_.sleep.end(), uint8_t(0));
  std::fill(nodes_.quiet.begin(), nodes_.quiet.end(), 0);
  awake_current_ = false;
}

void Model::restore_sleep_state(const std::vector<uint8_t>& sleep, const std::vector<int32_t>& quiet) {
  if (int64_t(sleep.size()) != nodes_.size() || int64_t(quiet.size()) != nodes_.size())
    bad("sleep state must have one entry per node (" + std::to_string(nodes_.size()) + ")");
  for (size_t i = 0; i < sleep.size(); ++i) {
    if (sleep[i] > 2) bad("sleep state of a node must be 0, 1 or 2 (node " + std::to_string(i) + ")");
    if (quiet[i] < 0) bad("quiet step count of a node must be >= 0 (node " + std::to_string(i) + ")");
  }
  nodes_.sleep = sleep;
  nodes_.quiet = quiet;
  awake_current_ = false;
  compute_all_next_ = true;
}

int32_t Model::asleep_nodes() const {
  return int32_t(std::count_if(nodes_.sleep.begin(), nodes_.sleep.end(), [](uint8_t s) { return s != 0; }));
}

int32_t Model::awake_triangles() {
  if (!sleep_.on) return tris_.size();
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

}  // namespace engine
