// Boundary conditions on the model's nodes: registration, constraint masks,
// the per-step reaction that lands a node on its prescribed velocity.
#include "common/input_errors.hpp"
#include "model/model.hpp"
#include "loads/boundary_kernel.hpp"

#include <cmath>

namespace engine {

void Model::add_boundary_condition(const BoundaryCondition& bc) {
  const std::string where = "boundary condition '" + bc.name + "'";
  if (bc.nodes.empty()) bad(where + ": node set is empty");
  for (int32_t id : bc.nodes)
    if (id < 0 || id >= nodes_.size())
      bad(where + ": node id " + std::to_string(id) + " out of range [0, " +
          std::to_string(nodes_.size() - 1) + "]");
  if (!bc.x && !bc.y) bad(where + ": constrains no component (x and y both off)");
  if (!std::isfinite(bc.dir_x) || !std::isfinite(bc.dir_y)) bad(where + ": direction must be finite");
  bc.history.validate(where);
  for (const BoundaryCondition& other : bcs_) {
    if (other.name == bc.name) bad(where + ": name already used");
    for (int32_t a : bc.nodes)
      for (int32_t b : other.nodes)
        if (a == b && ((bc.x && other.x) || (bc.y && other.y)))
          bad(where + ": node " + std::to_string(a) + " is already constrained by '" + other.name + "'");
  }
  bcs_.push_back(bc);
  for (int32_t id : bc.nodes) {  // held nodes never sleep
    nodes_.sleep[id] = 0;
    nodes_.quiet[id] = 0;
  }
  awake_current_ = false;
  prepared_ = false;
}

void Model::clear_boundary_conditions() {
  bcs_.clear();
  prepared_ = false;
}

int32_t Model::find_boundary_condition(const std::string& name) const {
  for (size_t i = 0; i < bcs_.size(); ++i)
    if (bcs_[i].name == name) return int32_t(i);
  return -1;
}

void Model::build_constraints() {
  std::fill(nodes_.constrained.begin(), nodes_.constrained.end(), 0);
  std::fill(nodes_.r_x.begin(), nodes_.r_x.end(), 0.0);
  std::fill(nodes_.r_y.begin(), nodes_.r_y.end(), 0.0);
  for (const BoundaryCondition& bc : bcs_)
    for (int32_t id : bc.nodes) nodes_.constrained[id] |= (bc.x ? 1 : 0) | (bc.y ? 2 : 0);
}

void Model::reaction(const std::vector<int32_t>& ids, double& rx, double& ry) const {
  sum_reactions(nodes_.r_x, nodes_.r_y, ids, rx, ry);
}

void Model::sum_reactions(const std::vector<double>& r_x, const std::vector<double>& r_y,
                          const std::vector<int32_t>& ids, double& rx, double& ry) {
  const int64_t n = int64_t(r_x.size());
  rx = ry = 0.0;
  for (int32_t id : ids) {
    if (id < 0 || id >= n) bad("node id " + std::to_string(id) + " out of range [0, " + std::to_string(n - 1) + "]");
    rx += r_x[size_t(id)];
    ry += r_y[size_t(id)];
  }
}

void Model::apply_boundary_conditions() {
  // loads/boundary_kernel.hpp, per node of each condition
  const double inv_dt = dt_ > 0.0 ? 1.0 / dt_ : 0.0;
  const double t_half = time_ + 0.5 * dt_;
  Nodes& N = nodes_;
  const BoundaryComponent cx{N.mass.data(), N.vx.data(), N.f_x.data(), N.v_bc_x.data(), N.r_x.data()};
  const BoundaryComponent cy{N.mass.data(), N.vy.data(), N.f_y.data(), N.v_bc_y.data(), N.r_y.data()};
  for (const BoundaryCondition& bc : bcs_) {
    const double s = bc.history.at(t_half);
    const double ux = bc.dir_x * s, uy = bc.dir_y * s;
    for (int32_t i : bc.nodes) {
      if (bc.x) prescribe_component(cx, i, ux, inv_dt);
      if (bc.y) prescribe_component(cy, i, uy, inv_dt);
    }
  }
}

}  // namespace engine
