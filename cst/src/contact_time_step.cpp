// Critical time step of the contact penalty; the estimate is derived in
// contact.hpp (ContactStableStep).
#include <algorithm>
#include <cmath>
#include <vector>

#include "contact.hpp"

namespace cst {

ContactStableStep contact_critical_dt(const ContactParams& p, const ContactInput& in,
                                      std::vector<double>* node_stiffness) {
  check_contact_params(p);
  if (node_stiffness) node_stiffness->assign(in.n_nodes, 0.0);
  ContactStableStep out;
  out.dt = INFINITY;
  // Each body on its own: an edge is a boundary edge of a body if no other
  // triangle of the same body uses it, and a node shared by several bodies
  // (a freeze-bond point of a continuous mesh) counts once per body with that
  // body's share of its mass. That is the state after the bond points split,
  // so a step chosen before the run stays stable through every split. Without
  // shared nodes this is the plain per-node estimate.
  struct Edge {
    int32_t a, b, body, tri, opp;  // end nodes (a < b), body, triangle, opposite node
  };
  std::vector<Edge> edges;
  edges.reserve(3 * static_cast<size_t>(in.n_tri));
  for (int32_t t = 0; t < in.n_tri; ++t) {
    const int32_t* v = in.tri + 3 * static_cast<int64_t>(t);
    for (int k = 0; k < 3; ++k) {
      const int32_t a = v[(k + 1) % 3], b = v[(k + 2) % 3];
      edges.push_back({std::min(a, b), std::max(a, b), in.body[t], t, v[k]});
    }
  }
  std::sort(edges.begin(), edges.end(), [](const Edge& e, const Edge& f) {
    if (e.a != f.a) return e.a < f.a;
    if (e.b != f.b) return e.b < f.b;
    return e.body != f.body ? e.body < f.body : e.tri < f.tri;
  });
  struct Share {
    int32_t node, body;
    double k, area;
  };
  std::vector<Share> shares;  // (node, body) contributions, merged below
  std::vector<double> len, alt;
  std::vector<int32_t> ea, eb, ebody;
  double a_min = INFINITY;
  for (size_t i = 0; i < edges.size();) {
    size_t j = i + 1;
    while (j < edges.size() && edges[j].a == edges[i].a && edges[j].b == edges[i].b &&
           edges[j].body == edges[i].body)
      ++j;
    if (j == i + 1) {
      const Edge& e = edges[i];
      const double ex = in.x[e.b] - in.x[e.a], ey = in.y[e.b] - in.y[e.a];
      const double l = std::hypot(ex, ey);
      const double area2 = std::fabs(ex * (in.y[e.opp] - in.y[e.a]) - ey * (in.x[e.opp] - in.x[e.a]));
      if (l > 0.0 && area2 > 0.0) {
        const double a = area2 / l;
        len.push_back(l);
        alt.push_back(a);
        ea.push_back(e.a);
        eb.push_back(e.b);
        ebody.push_back(e.body);
        a_min = std::min(a_min, a);
      }
    }
    i = j;
  }
  if (len.empty()) return out;
  for (size_t e = 0; e < len.size(); ++e) {
    const double ke = 1.5 * p.penalty * len[e] * (1.0 / alt[e] + 1.0 / a_min);
    shares.push_back({ea[e], ebody[e], ke, 0.0});
    shares.push_back({eb[e], ebody[e], ke, 0.0});
  }
  // Mass share of each body at a node: its triangles' share of the area around
  // the node (lumped masses are 1/3 of each triangle's mass; equal densities
  // of the bodies meeting at a node are assumed, as for ice on ice).
  std::vector<double> node_area(in.n_nodes, 0.0);
  for (int32_t t = 0; t < in.n_tri; ++t) {
    const int32_t* v = in.tri + 3 * static_cast<int64_t>(t);
    const double A = 0.5 * std::fabs((in.x[v[1]] - in.x[v[0]]) * (in.y[v[2]] - in.y[v[0]]) -
                                     (in.x[v[2]] - in.x[v[0]]) * (in.y[v[1]] - in.y[v[0]]));
    for (int k = 0; k < 3; ++k) {
      node_area[v[k]] += A;
      shares.push_back({v[k], in.body[t], 0.0, A});
    }
  }
  std::sort(shares.begin(), shares.end(), [](const Share& a, const Share& b) {
    return a.node != b.node ? a.node < b.node : a.body < b.body;
  });
  for (size_t i = 0; i < shares.size();) {
    size_t j = i;
    double k = 0.0, area = 0.0;
    while (j < shares.size() && shares[j].node == shares[i].node && shares[j].body == shares[i].body) {
      k += shares[j].k;
      area += shares[j].area;
      ++j;
    }
    const int32_t n = shares[i].node;
    const double m = node_area[n] > 0.0 ? in.mass[n] * area / node_area[n] : 0.0;
    i = j;
    if (node_stiffness && k > 0.0 && area > 0.0)
      (*node_stiffness)[n] = std::max((*node_stiffness)[n], k * node_area[n] / area);
    if (!(k > 0.0) || !(m > 0.0) || !std::isfinite(m)) continue;
    const double dt = std::sqrt(2.0 * m / k);
    if (dt < out.dt) {
      out.dt = dt;
      out.node = n;
      out.stiffness = k;
      out.mass = m;
    }
  }
  return out;
}

}  // namespace cst
