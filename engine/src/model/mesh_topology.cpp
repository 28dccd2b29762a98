// The mesh the model is built on and its edits: reference geometry, the
// node -> corner gather list, body surfaces, and node splitting.
#include "common/bucket_sort.hpp"
#include "common/input_errors.hpp"
#include "model/model.hpp"

#include <algorithm>
#include <cmath>

namespace engine {

Model::Model(const std::vector<double>& xy, const std::vector<int32_t>& tri,
             const std::vector<int32_t>& body) {
  if (xy.size() % 2 != 0 || xy.empty()) bad("nodes must be an (N, 2) array with N >= 3");
  if (tri.size() % 3 != 0 || tri.empty()) bad("triangles must be an (M, 3) array with M >= 1");
  const int64_t n = int64_t(xy.size() / 2), m = int64_t(tri.size() / 3);
  if (n > INT32_MAX / 2 || m > INT32_MAX / 6) bad("mesh too large for 32-bit ids");
  if (int64_t(body.size()) != m)
    bad("body must have one id per triangle (" + std::to_string(m) + "), got " +
        std::to_string(body.size()));
  for (double v : xy)
    if (!std::isfinite(v)) bad("nodes must be finite");
  int32_t n_bodies = 0;
  for (int64_t t = 0; t < m; ++t) {
    if (body[t] < 0) bad("body ids must be >= 0 (triangle " + std::to_string(t) + ")");
    n_bodies = std::max(n_bodies, body[t] + 1);
    for (int c = 0; c < 3; ++c) {
      const int32_t id = tri[3 * t + c];
      if (id < 0 || id >= n)
        bad("triangle " + std::to_string(t) + " uses node " + std::to_string(id) +
            ": node ids must be in [0, " + std::to_string(n - 1) + "]");
    }
  }
  nodes_.resize(int32_t(n));
  for (int64_t i = 0; i < n; ++i) {
    nodes_.x[i] = nodes_.x0[i] = xy[2 * i];
    nodes_.y[i] = nodes_.y0[i] = xy[2 * i + 1];
  }
  tris_.resize(int32_t(m));
  std::copy(tri.begin(), tri.end(), tris_.node.begin());
  std::copy(body.begin(), body.end(), tris_.body.begin());
  for (int32_t t = 0; t < int32_t(m); ++t) {
    const int32_t a = tri[3 * t], b = tri[3 * t + 1], c = tri[3 * t + 2];
    const double A = element_reference(nodes_.x0[a], nodes_.y0[a], nodes_.x0[b], nodes_.y0[b],
                                       nodes_.x0[c], nodes_.y0[c], tris_.binv00[t],
                                       tris_.binv01[t], tris_.binv10[t], tris_.binv11[t]);
    double longest = 0.0;
    for (int k = 0; k < 3; ++k) {
      const int32_t p = tri[3 * t + k], q = tri[3 * t + (k + 1) % 3];
      longest = std::max(longest, std::hypot(nodes_.x0[q] - nodes_.x0[p], nodes_.y0[q] - nodes_.y0[p]));
    }
    // A sliver whose area is round-off of its edge lengths has no usable Dm^-1.
    if (!(A > 1e-10 * longest * longest))
      bad("triangle " + std::to_string(t) + " (nodes " + std::to_string(a) + ", " +
          std::to_string(b) + ", " + std::to_string(c) + ") has signed area " + num(A) +
          " m²: triangles must be counter-clockwise and not degenerate (area > 1e-10 x longest edge²)");
    tris_.area0[t] = A;
  }
  materials_.assign(n_bodies, Material{});
  rebuild_topology();
}

void Model::rebuild_topology() {
  const int32_t n = nodes_.size(), m = tris_.size();
  ++topology_version_;
  // Node -> corner gather list, corners in ascending slot order.
  gather_.start.assign(size_t(n) + 1, 0);
  for (int32_t s = 0; s < 3 * m; ++s) {
    const int32_t id = tris_.node[s];
    if (id < 0 || id >= n)
      bad("triangle " + std::to_string(s / 3) + " uses node " + std::to_string(id) +
          ": node ids must be in [0, " + std::to_string(n - 1) + "]");
    ++gather_.start[id + 1];
  }
  for (int32_t i = 0; i < n; ++i) {
    if (gather_.start[i + 1] == 0)
      bad("node " + std::to_string(i) + " is not used by any triangle (it would have no mass)");
    gather_.start[i + 1] += gather_.start[i];
  }
  gather_.slot.resize(size_t(3) * m);
  {
    std::vector<int32_t> fill(gather_.start.begin(), gather_.start.end() - 1);
    for (int32_t s = 0; s < 3 * m; ++s) gather_.slot[fill[tris_.node[s]]++] = s;
  }
  node_body_.resize(size_t(n));
  for (int32_t i = 0; i < n; ++i) node_body_[i] = tris_.body[gather_.slot[gather_.start[i]] / 3];
  // Boundary edges of each body: used by one triangle of that body only. The
  // mesh may be continuous across bodies (freeze bonds), so count per body.
  struct Edge {
    int32_t a, b, body;  // a < b
  };
  std::vector<Edge> edges;
  edges.reserve(size_t(3) * m);
  for (int32_t t = 0; t < m; ++t)
    for (int c = 0; c < 3; ++c) {
      const int32_t a = tris_.node[3 * t + c], b = tris_.node[3 * t + (c + 1) % 3];
      edges.push_back({std::min(a, b), std::max(a, b), tris_.body[t]});
    }
  // grouped by node: a split rebuilds this over the whole mesh (common/bucket_sort.hpp)
  bucket_sort(edges, n, [](const Edge& e) { return e.a; },
              [](const Edge& e, const Edge& f) { return e.b != f.b ? e.b < f.b : e.body < f.body; });
  auto same = [](const Edge& e, const Edge& f) { return e.a == f.a && e.b == f.b && e.body == f.body; };
  on_surface_.assign(n, 0);
  for (size_t i = 0; i < edges.size();) {
    size_t j = i + 1;
    while (j < edges.size() && same(edges[j], edges[i])) ++j;
    if (j - i == 1) on_surface_[edges[i].a] = on_surface_[edges[i].b] = 1;
    i = j;
  }
  surface_tris_.clear();
  std::vector<uint8_t> body_used(materials_.size(), 0);
  for (int32_t t = 0; t < m; ++t) {
    body_used[tris_.body[t]] = 1;
    const int32_t* c = &tris_.node[3 * t];
    if (on_surface_[c[0]] || on_surface_[c[1]] || on_surface_[c[2]]) surface_tris_.push_back(t);
  }
  body_tris_.build(tris_, surface_tris_, int32_t(materials_.size()), n);
  contact_possible_ = std::count(body_used.begin(), body_used.end(), 1) >= 2;
  prepared_ = false;
  stable_current_ = false;
}

int32_t Model::add_node(double x, double y, double x0, double y0, double vx, double vy) {
  const int32_t id = nodes_.size();
  nodes_.resize(id + 1);
  nodes_.x[id] = x;
  nodes_.y[id] = y;
  nodes_.x0[id] = x0;
  nodes_.y0[id] = y0;
  nodes_.vx[id] = vx;
  nodes_.vy[id] = vy;
  prepared_ = false;
  awake_current_ = false;
  return id;
}

void Model::set_triangle_node(int32_t tri, int corner, int32_t node) {
  if (tri < 0 || tri >= tris_.size()) bad("tri must be in [0, " + std::to_string(tris_.size() - 1) + "]");
  if (corner < 0 || corner > 2) bad("corner must be 0, 1 or 2");
  if (node < 0 || node >= nodes_.size()) bad("node must be in [0, " + std::to_string(nodes_.size() - 1) + "]");
  const int32_t was = tris_.node[3 * tri + corner];
  // the triangle's reference shape (Dm^-1, area, its limit) is the constructor's
  if (nodes_.x0[node] != nodes_.x0[was] || nodes_.y0[node] != nodes_.y0[was])
    bad("set_triangle_node: node " + std::to_string(node) + " is at (" + num(nodes_.x0[node]) + ", " +
        num(nodes_.y0[node]) + ") m in the reference configuration, corner " + std::to_string(corner) +
        " of triangle " + std::to_string(tri) + " at (" + num(nodes_.x0[was]) + ", " + num(nodes_.y0[was]) +
        ") m: a corner can only be re-pointed to a node at its own reference place (a split)");
  ref_stiffness_stale_ = true;  // the contact stiffness too (not a split: a rename would not do)
  tris_.node[3 * tri + corner] = node;
  prepared_ = false;
  awake_current_ = false;
}

int32_t Model::split_off(int32_t node, int32_t body) {
  const int32_t id = add_node(nodes_.x[node], nodes_.y[node], nodes_.x0[node], nodes_.y0[node],
                              nodes_.vx[node], nodes_.vy[node]);
  // a bond event wakes every body at the bond point (its forces change): all
  // bodies with a corner at the node, before the corners are re-pointed
  if (body_wake_.size() != size_t(n_bodies())) body_wake_.assign(size_t(n_bodies()), 0);
  for (int32_t j = gather_.start[node]; j < gather_.start[node + 1]; ++j) {
    const int32_t s = gather_.slot[j];
    body_wake_[tris_.body[s / 3]] = 1;
    if (tris_.body[s / 3] == body) tris_.node[s] = id;
  }
  ref_stiffness_renames_.push_back({node, body, id});  // the contact stiffness follows (forces.cpp)
  for (BoundaryCondition& bc : bcs_)
    if (std::find(bc.nodes.begin(), bc.nodes.end(), node) != bc.nodes.end()) bc.nodes.push_back(id);
  nodes_.mass_floor[id] = nodes_.mass_floor[node];  // each side keeps what the node needed
  nodes_.sleep[node] = nodes_.sleep[id] = 0;
  nodes_.quiet[node] = nodes_.quiet[id] = 0;
  return id;
}

void Model::regather_node(int32_t i) {
  gather_node(i, any_damping_, params_.external.water(), params_.external.buoyancy, params_.external.drag_on(), params_.external.gravity ? params_.external.g : 0.0);
}

bool Model::node_touches_body(int32_t node, int32_t body) const {
  for (int32_t j = gather_.start[node]; j < gather_.start[node + 1]; ++j)
    if (tris_.body[gather_.slot[j] / 3] == body) return true;
  return false;
}

int32_t Model::body_of_node(int32_t node) const {
  if (node < 0 || size_t(node) >= node_body_.size()) return -1;
  return node_body_[node];
}

}  // namespace engine
