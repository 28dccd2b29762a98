// Critical time step of the contact penalty; the estimate is derived in
// contact.hpp (ContactStableStep).
#include <algorithm>
#include <cmath>
#include <vector>

#include "contact.hpp"

namespace cst {

ContactStableStep contact_critical_dt(const ContactParams& p, const ContactInput& in) {
  check_contact_params(p);
  ContactStableStep out;
  out.dt = INFINITY;
  struct Edge {
    int32_t a, b, tri, opp;  // end nodes (a < b), triangle, opposite node
  };
  std::vector<Edge> edges;
  edges.reserve(3 * static_cast<size_t>(in.n_tri));
  for (int32_t t = 0; t < in.n_tri; ++t) {
    const int32_t* v = in.tri + 3 * static_cast<int64_t>(t);
    for (int k = 0; k < 3; ++k) {
      const int32_t a = v[(k + 1) % 3], b = v[(k + 2) % 3];
      edges.push_back({std::min(a, b), std::max(a, b), t, v[k]});
    }
  }
  std::sort(edges.begin(), edges.end(), [](const Edge& e, const Edge& f) {
    return e.a != f.a ? e.a < f.a : (e.b != f.b ? e.b < f.b : e.tri < f.tri);
  });
  // Boundary edges: used by exactly one triangle. Length and altitude of each.
  std::vector<double> len, alt;
  std::vector<int32_t> ea, eb;
  double a_min = INFINITY;
  for (size_t i = 0; i < edges.size();) {
    size_t j = i + 1;
    while (j < edges.size() && edges[j].a == edges[i].a && edges[j].b == edges[i].b) ++j;
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
        a_min = std::min(a_min, a);
      }
    }
    i = j;
  }
  if (len.empty()) return out;
  std::vector<double> k(in.n_nodes, 0.0);
  for (size_t e = 0; e < len.size(); ++e) {
    const double ke = 1.5 * p.penalty * len[e] * (1.0 / alt[e] + 1.0 / a_min);
    k[ea[e]] += ke;
    k[eb[e]] += ke;
  }
  for (int32_t i = 0; i < in.n_nodes; ++i) {
    const double m = in.mass[i];
    if (!(k[i] > 0.0) || !(m > 0.0) || !std::isfinite(m)) continue;
    const double dt = std::sqrt(2.0 * m / k[i]);
    if (dt < out.dt) {
      out.dt = dt;
      out.node = i;
      out.stiffness = k[i];
      out.mass = m;
    }
  }
  return out;
}

}  // namespace cst
