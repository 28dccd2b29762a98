// The state a caller may set or restore (positions, velocities, clock,
// energy ledger) and the memory held.
#include "common/input_errors.hpp"
#include "model/model.hpp"

#include <cmath>

namespace engine {

void Model::set_positions(const std::vector<double>& x, const std::vector<double>& y) {
  if (int64_t(x.size()) != nodes_.size() || int64_t(y.size()) != nodes_.size())
    bad("positions must have one row per node (" + std::to_string(nodes_.size()) + ")");
  for (size_t i = 0; i < x.size(); ++i)
    if (!std::isfinite(x[i]) || !std::isfinite(y[i])) bad("positions must be finite");
  nodes_.x = x;
  nodes_.y = y;
  wake_all();  // stored forces of sleeping triangles no longer hold
  reset_energy();
}

void Model::set_velocities(const std::vector<double>& vx, const std::vector<double>& vy) {
  if (int64_t(vx.size()) != nodes_.size() || int64_t(vy.size()) != nodes_.size())
    bad("velocities must have one row per node (" + std::to_string(nodes_.size()) + ")");
  for (size_t i = 0; i < vx.size(); ++i)
    if (!std::isfinite(vx[i]) || !std::isfinite(vy[i])) bad("velocities must be finite");
  nodes_.vx = vx;
  nodes_.vy = vy;
  wake_all();
  reset_energy();
}

void Model::reset_energy() { energy_ = EnergyLedger{}; }

void Model::restore_clock(double time, int64_t step_count) {
  if (!std::isfinite(time)) bad("time must be finite (got " + num(time) + ")");
  if (step_count < 0) bad("step_count must be >= 0 (got " + std::to_string(step_count) + ")");
  time_ = time;
  step_count_ = step_count;
}

void Model::restore_step_fields(const std::vector<double>& r_x, const std::vector<double>& r_y,
                                const std::vector<double>& stress) {
  if (r_x.size() != size_t(nodes_.size()) || r_y.size() != size_t(nodes_.size()))
    bad("reactions: " + std::to_string(nodes_.size()) + " per component expected (got " +
        std::to_string(r_x.size()) + ", " + std::to_string(r_y.size()) + ")");
  if (stress.size() != tris_.stress.size())
    bad("stress: " + std::to_string(tris_.stress.size()) + " values expected (got " + std::to_string(stress.size()) +
        ")");
  nodes_.r_x = r_x;
  nodes_.r_y = r_y;
  tris_.stress = stress;
}

size_t Model::memory_bytes() const {
  size_t b = nodes_.bytes() + tris_.bytes() + gather_.bytes() + on_surface_.capacity() +
             surface_tris_.capacity() * sizeof(int32_t) +
             body_tris_.bytes() + partial_.capacity() * sizeof(ThreadSums) +
             bonds_.memory_bytes();
  for (const BoundaryCondition& bc : bcs_) b += bc.nodes.capacity() * sizeof(int32_t);
  return b;
}

}  // namespace engine
