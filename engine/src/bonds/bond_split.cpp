// Node splitting at a failing bond point (paper section 2.3.2, Fig. 3) and the
// initial cohesive force of eq 8.
//
// The point's node becomes one node per body meeting there (two for an
// ordinary bond point, more at a junction): the body with the highest id keeps
// the node, every other body gets a new node at the same place with the same
// velocity, and its triangles are re-pointed to it. Masses then come from the
// elements on each side (m+ + m- = m). The forces of the current step are
// shared the same way: element, buoyancy and drag forces per corner, gravity
// per mass, and the node's contact force in proportion to mass.
#include <algorithm>
#include <cmath>

#include "cohesive_law/softening.hpp"
#include "bonds/freeze_bonds.hpp"

namespace engine {

namespace cl = cohesive_law;

void FreezeBonds::split_force(const BondHost& M, int32_t k, double& gx, double& gy) const {
  // Eq 8 with the elastic element forces: the paper's internal forces "for
  // the stress state t_e = sigma_cr". (The force that holds an opened pair in
  // its rigid phase is bonds/cohesive_pair_kernel.hpp's bond_holding_force.)
  const Nodes& N = M.nodes();
  const int32_t a = st_.node_plus[k], b = st_.node_minus[k];
  eq8_force(N.mass[a], N.mass[b], N.f_int_x[a] - N.f_visc_x[a], N.f_int_y[a] - N.f_visc_y[a],
            N.f_int_x[b] - N.f_visc_x[b], N.f_int_y[b] - N.f_visc_y[b], gx, gy);
}

void FreezeBonds::split_points(BondHost& M, const std::vector<int32_t>& points) {
  const BondHost& CM = M;
  const Nodes& N = CM.nodes();
  const Triangles& T = CM.triangles();
  const NodeGather& gather = CM.gather();
  const double time = M.time();
  // Per split point: its nodes (one per body, bodies ascending), and what the
  // unsplit node carried that is not per corner.
  struct Group {
    int32_t point;
    std::vector<int32_t> bodies, nodes;
    double mass, fcx, fcy;
  };
  std::vector<Group> groups;
  groups.reserve(points.size());
  const std::vector<double> mass_before = N.mass;
  std::vector<int32_t> split_parent;  // of each node split off, in id order
  for (int32_t p : points) {
    const int32_t i = in_.node[p];
    Group G;
    G.point = p;
    G.mass = N.mass[i];
    G.fcx = N.f_con_x[i];
    G.fcy = N.f_con_y[i];
    for (int32_t j = gather.start[i]; j < gather.start[i + 1]; ++j)
      G.bodies.push_back(T.body[gather.slot[j] / 3]);
    std::sort(G.bodies.begin(), G.bodies.end());
    G.bodies.erase(std::unique(G.bodies.begin(), G.bodies.end()), G.bodies.end());
    G.nodes.assign(G.bodies.size(), i);
    // The highest body keeps node i; the others get new nodes.
    for (size_t b = 0; b + 1 < G.bodies.size(); ++b) {
      G.nodes[b] = M.split_off(i, G.bodies[b]);
      st_.parent.push_back(i);
      split_parent.push_back(i);
    }
    st_.point_state[p] = PointState::split;
    st_.t_split[p] = time;
    st_.x_split[p] = N.x[i];
    st_.y_split[p] = N.y[i];
    groups.push_back(std::move(G));
  }
  M.prepare_topology();  // gather list, surface triangles, masses, constraints
  Nodes& W = M.bond_nodes();

  for (const Group& G : groups) {
    // Forces of this step on each new node; contact shared by mass, the last
    // node taking the remainder so the total is unchanged.
    double rx = G.fcx, ry = G.fcy;
    // Without mass scaling the pieces add up to G.mass (to round-off, which
    // must not move the shares); with it, to what the sides now need.
    double pieces = 0.0;
    for (int32_t id : G.nodes) pieces += N.mass[id];
    if (std::fabs(pieces - G.mass) <= BondHost::kSameMass * G.mass) pieces = G.mass;
    for (size_t b = 0; b < G.nodes.size(); ++b) {
      const int32_t id = G.nodes[b];
      M.regather_node(id);
      if (b + 1 < G.nodes.size()) {
        const double w = N.mass[id] / pieces;
        W.f_con_x[id] = G.fcx * w;
        W.f_con_y[id] = G.fcy * w;
        rx -= N.f_con_x[id];
        ry -= N.f_con_y[id];
      } else {
        W.f_con_x[id] = rx;
        W.f_con_y[id] = ry;
      }
    }
    // Cohesive pairs of the point.
    const int32_t p = G.point;
    for (int32_t k = first_pair_[p]; k < first_pair_[p] + n_pairs_[p]; ++k) {
      const auto node_of = [&](int32_t body) {
        const size_t b = std::lower_bound(G.bodies.begin(), G.bodies.end(), body) - G.bodies.begin();
        return G.nodes[b];
      };
      st_.node_plus[k] = node_of(in_.body_plus[k]);
      st_.node_minus[k] = node_of(in_.body_minus[k]);
      // The bond frame is frozen at the split (the paper's fixed n).
      bond_current_normal(check_arrays(M), k, st_.fnx[k], st_.fny[k]);
      st_.split_tn[k] = tn_[k];
      st_.split_tt[k] = tt_[k];
      double gx, gy;
      split_force(M, k, gx, gy);
      const double gn = gx * st_.fnx[k] + gy * st_.fny[k], gt = -gx * st_.fny[k] + gy * st_.fnx[k];
      const double beta = beta_[p];
      st_.f0[k] = cl::initial_effective_force(gn, gt, beta, params_.direction);
      st_.delta_m[k] = 0.0;
      st_.d_n_prev[k] = st_.d_t_prev[k] = 0.0;
      st_.f_n_prev[k] = st_.f_t_prev[k] = 0.0;
      if (st_.f0[k] > 0.0 && std::isfinite(st_.f0[k])) {
        st_.delta_f[k] = cl::critical_opening(in_.G[p], in_.length[k], st_.f0[k]);
        st_.pair_state[k] = PairState::cohesive;
      } else {
        // Nothing to hold (an unloaded pair of a junction): broken at once.
        st_.f0[k] = 0.0;
        st_.delta_f[k] = 0.0;
        st_.pair_state[k] = PairState::failed;
        st_.t_fail[k] = time;
        st_.x_fail[k] = st_.x_split[p];
        st_.y_fail[k] = st_.y_split[p];
        st_.dn_fail[k] = st_.dt_fail[k] = 0.0;
        st_.mode[k] = cl::failure_mode(0.0, 0.0);
      }
    }
  }
  // after the regather: the books need the pieces' elastic forces
  M.keep_momentum_through_split(mass_before, split_parent);
}

}  // namespace engine
