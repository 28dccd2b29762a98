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
#include "model/model.hpp"

namespace engine {

namespace cl = cohesive_law;

void FreezeBonds::regather(Model& M, int32_t i) const {
  const ExternalParams& x = M.ext_;
  M.gather_node(i, M.any_damping_, x.water(), x.buoyancy, x.drag_on(), x.gravity ? x.g : 0.0);
}

void FreezeBonds::split_force(const Model& M, int32_t k, bool elastic, double& gx,
                              double& gy) const {
  // Eq 8 as a vector: with g on the + node and -g on the - node both move with
  // the acceleration (F+ + F-)/(m+ + m-) of the unsplit node.
  //   elastic: F = the elastic element forces (the paper's internal forces "for
  //            the stress state t_e = sigma_cr"): gives f0.
  //   else:    the force that keeps the pair together: F = every force of the
  //            step but friction and the cohesive pairs (gravity, drag and the
  //            contact share are proportional to mass and nearly drop out),
  //            plus m_r (v- - v+)/dt, which also stops a relative velocity the
  //            pair already has (stick of a rigid-plastic link; 0 at the split,
  //            where both nodes share the velocity).
  const Nodes& N = M.nodes_;
  const int32_t a = node_plus_[k], b = node_minus_[k];
  const double mp = N.mass[a], mm = N.mass[b];
  double Fpx, Fpy, Fmx, Fmy;
  if (elastic) {
    Fpx = N.f_int_x[a] - N.f_visc_x[a];
    Fpy = N.f_int_y[a] - N.f_visc_y[a];
    Fmx = N.f_int_x[b] - N.f_visc_x[b];
    Fmy = N.f_int_y[b] - N.f_visc_y[b];
  } else {
    Fpx = N.f_x[a] + N.f_con_x[a];
    Fpy = N.f_y[a] + N.f_con_y[a];
    Fmx = N.f_x[b] + N.f_con_x[b];
    Fmy = N.f_y[b] + N.f_con_y[b];
  }
  const double m = mp + mm;
  gx = (-mm * Fpx + mp * Fmx) / m;
  gy = (-mm * Fpy + mp * Fmy) / m;
  if (!elastic) {
    const double s = mp * mm / (m * M.dt());
    gx += s * (N.vx[b] - N.vx[a]);
    gy += s * (N.vy[b] - N.vy[a]);
  }
}

void FreezeBonds::split_points(Model& M, const std::vector<int32_t>& points) {
  Nodes& N = M.nodes_;
  Triangles& T = M.tris_;
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
  for (int32_t p : points) {
    const int32_t i = node_[p];
    Group G;
    G.point = p;
    G.mass = N.mass[i];
    G.fcx = N.f_con_x[i];
    G.fcy = N.f_con_y[i];
    std::vector<int32_t> slots(M.gather_.slot.begin() + M.gather_.start[i],
                               M.gather_.slot.begin() + M.gather_.start[i + 1]);
    for (int32_t s : slots) G.bodies.push_back(T.body[s / 3]);
    std::sort(G.bodies.begin(), G.bodies.end());
    G.bodies.erase(std::unique(G.bodies.begin(), G.bodies.end()), G.bodies.end());
    G.nodes.assign(G.bodies.size(), i);
    // The highest body keeps node i; the others get new nodes.
    for (size_t b = 0; b + 1 < G.bodies.size(); ++b) {
      const int32_t id = M.add_node(N.x[i], N.y[i], N.x0[i], N.y0[i], N.vx[i], N.vy[i]);
      G.nodes[b] = id;
      parent_.push_back(i);
      for (int32_t s : slots)
        if (T.body[s / 3] == G.bodies[b]) T.node[s] = id;
      // A prescribed node stays prescribed on every side.
      for (BoundaryCondition& bc : M.bcs_)
        if (std::find(bc.nodes.begin(), bc.nodes.end(), i) != bc.nodes.end()) bc.nodes.push_back(id);
    }
    point_state_[p] = 1;
    t_split_[p] = time;
    x_split_[p] = N.x[i];
    y_split_[p] = N.y[i];
    groups.push_back(std::move(G));
  }
  M.prepared_ = false;
  M.prepare_topology();  // gather list, surface triangles, masses, constraints

  for (const Group& G : groups) {
    // Forces of this step on each new node; contact shared by mass, the last
    // node taking the remainder so the total is unchanged.
    double rx = G.fcx, ry = G.fcy;
    for (size_t b = 0; b < G.nodes.size(); ++b) {
      const int32_t id = G.nodes[b];
      regather(M, id);
      if (b + 1 < G.nodes.size()) {
        const double w = N.mass[id] / G.mass;
        N.f_con_x[id] = G.fcx * w;
        N.f_con_y[id] = G.fcy * w;
        rx -= N.f_con_x[id];
        ry -= N.f_con_y[id];
      } else {
        N.f_con_x[id] = rx;
        N.f_con_y[id] = ry;
      }
    }
    // Cohesive pairs of the point.
    const int32_t p = G.point;
    for (int32_t k = first_pair_[p]; k < first_pair_[p] + n_pairs_[p]; ++k) {
      const auto node_of = [&](int32_t body) {
        const size_t b = std::lower_bound(G.bodies.begin(), G.bodies.end(), body) - G.bodies.begin();
        return G.nodes[b];
      };
      node_plus_[k] = node_of(body_plus_[k]);
      node_minus_[k] = node_of(body_minus_[k]);
      // The bond frame is frozen at the split (the paper's fixed n).
      current_normal(M, k, fnx_[k], fny_[k]);
      split_tn_[k] = tn_[k];
      split_tt_[k] = tt_[k];
      double gx, gy;
      split_force(M, k, true, gx, gy);
      const double gn = gx * fnx_[k] + gy * fny_[k], gt = -gx * fny_[k] + gy * fnx_[k];
      const double beta = beta_[p];
      f0_[k] = cl::initial_effective_force(gn, gt, beta, params_.direction);
      delta_m_[k] = 0.0;
      d_n_prev_[k] = d_t_prev_[k] = 0.0;
      f_n_prev_[k] = f_t_prev_[k] = 0.0;
      if (f0_[k] > 0.0 && std::isfinite(f0_[k])) {
        delta_f_[k] = cl::critical_opening(G_[p], l_[k], f0_[k]);
        pair_state_[k] = 1;
      } else {
        // Nothing to hold (an unloaded pair of a junction): broken at once.
        f0_[k] = 0.0;
        delta_f_[k] = 0.0;
        pair_state_[k] = 2;
        t_fail_[k] = time;
        x_fail_[k] = x_split_[p];
        y_fail_[k] = y_split_[p];
        dn_fail_[k] = dt_fail_[k] = 0.0;
        mode_[k] = int8_t(cl::failure_mode(0.0, 0.0));
      }
    }
  }
}

}  // namespace engine
