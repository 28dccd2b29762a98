// Critical time step of the contact penalty; the estimate is derived in
// contact.hpp (ContactStableStep).
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "common/bucket_sort.hpp"
#include "contact/contact.hpp"

namespace engine {

namespace {

// The other body's share of a contactor edge's stiffness (contact.hpp): the
// edge, length l, pressed onto a stretch of boundary of length l, gets 3/2 s
// times the integral of 1/a' (a' the altitude of the target triangle under
// it) over that stretch. T(l) bounds it by the largest such integral over
// every window of length l along every body's boundary, so a sliver (small a')
// only counts over its own short edge: a regular mesh (l = a' = h) gives 1,
// as before, but a 3 mm edge of altitude 2 mm next to 0.15 m edges raises it
// to ~2.3, where the smallest altitude anywhere (l/a_min) gave 65.
// The integrand is piecewise constant, so the largest window has an end at a
// vertex: walk from every boundary vertex along each of its boundary edges,
// once, to the longest edge length, reading the integral at every length of a
// geometric grid (factor 1.1; an edge takes the grid length at or above its
// own, which only overestimates, the integral growing with the length). Where
// a body's boundary meets itself at a node every branch is followed.
// Tiny elements sit at junctions of blocks, so an edge can rest on two bodies
// (or bridge a notch of one) at once: the returned bound is
// T2(l) = max over l1 of T(l1) + T(l - l1), which is T(l) on a regular mesh.
// With a finite reach R, an edge e only counts the stretches of other bodies'
// boundaries it can meet: those starting at a vertex within R + l_e of it
// (a stretch of length l_e that comes within R of the edge starts there).
// Every window is read from the vertex it starts at, so T is kept per start
// vertex and maximised over the vertices near each edge (a grid of cells of
// size R + the longest edge).
std::vector<double> target_terms(const std::vector<double>& len, const std::vector<double>& alt,
                                 const std::vector<int32_t>& ea, const std::vector<int32_t>& eb,
                                 const std::vector<int32_t>& ebody, const double* x, const double* y,
                                 double reach) {
  const bool local = std::isfinite(reach);
  const size_t n = len.size();
  // boundary edges at each (body, node), for the walk
  struct End {
    int32_t body, node, edge;
  };
  std::vector<End> ends;
  ends.reserve(2 * n);
  for (size_t e = 0; e < n; ++e) {
    ends.push_back({ebody[e], ea[e], int32_t(e)});
    ends.push_back({ebody[e], eb[e], int32_t(e)});
  }
  auto key_less = [](const End& a, const End& b) {
    return a.body != b.body ? a.body < b.body : a.node != b.node ? a.node < b.node : a.edge < b.edge;
  };
  std::sort(ends.begin(), ends.end(), key_less);
  // first[k]..first[k+1]: the edges at the k-th distinct (body, node); at_end[2e+c]: the
  // index k of edge e's end c (0: ea, 1: eb)
  std::vector<size_t> first;
  std::vector<size_t> at_end(2 * n);
  for (size_t i = 0; i < ends.size(); ++i) {
    if (i == 0 || ends[i].body != ends[i - 1].body || ends[i].node != ends[i - 1].node)
      first.push_back(i);
    const int32_t e = ends[i].edge;
    at_end[2 * size_t(e) + (ea[e] == ends[i].node ? 0 : 1)] = first.size() - 1;
  }
  first.push_back(ends.size());

  const double l_lo = *std::min_element(len.begin(), len.end());
  const double l_hi = *std::max_element(len.begin(), len.end());
  std::vector<double> grid{l_lo};
  while (grid.back() < l_hi) grid.push_back(std::min(grid.back() * 1.1, l_hi));
  const size_t n_grid = grid.size();
  std::vector<double> T(n_grid, 0.0);
  const size_t n_vert = first.size() - 1;
  std::vector<double> W(local ? n_vert * n_grid : 0, 0.0);  // per start vertex: T of its windows

  // Depth-first walk: edge f entered at its end c, c0 the length walked so far,
  // s0 the integral so far, g the first grid length above c0.
  struct Frame {
    int32_t f;
    int c;
    double c0, s0;
    size_t g;
  };
  std::vector<Frame> stack;
  for (size_t e = 0; e < n; ++e)
    for (int c = 0; c < 2; ++c) {
      double* Tv = local ? W.data() + at_end[2 * e + c] * n_grid : T.data();
      stack.push_back({int32_t(e), c, 0.0, 0.0, 0});
      while (!stack.empty()) {
        const Frame fr = stack.back();
        stack.pop_back();
        const double d = 1.0 / alt[fr.f], c1 = fr.c0 + len[fr.f];
        size_t g = fr.g;
        for (; g < n_grid && grid[g] <= c1; ++g) Tv[g] = std::max(Tv[g], fr.s0 + (grid[g] - fr.c0) * d);
        if (g >= n_grid) continue;  // reached the longest length
        const double s1 = fr.s0 + len[fr.f] * d;
        const size_t k = at_end[2 * size_t(fr.f) + (1 - fr.c)];  // leave through the far end
        const int32_t v = fr.c == 0 ? eb[fr.f] : ea[fr.f];
        for (size_t i = first[k]; i < first[k + 1]; ++i) {
          const int32_t h = ends[i].edge;
          if (h == fr.f) continue;
          stack.push_back({h, ea[h] == v ? 0 : 1, c1, s1, g});
        }
      }
    }
  // T of any length up to l_hi: the grid value at or above it, and never more
  // than L times the largest density 1/a' (short lengths below the grid)
  double d_max = 0.0;
  for (double a : alt) d_max = std::max(d_max, 1.0 / a);
  // T2 at grid index g from a T function (grid values)
  auto T2_at = [&](const double* Tf, size_t g) {
    auto T_up = [&](double L) {
      if (!(L > 0.0)) return 0.0;
      const size_t h = std::lower_bound(grid.begin(), grid.end(), L) - grid.begin();
      return std::min(Tf[std::min(h, n_grid - 1)], L * d_max);
    };
    double t2 = Tf[g];
    for (size_t i = 0; i < g; ++i) t2 = std::max(t2, Tf[i] + T_up(grid[g] - grid[i]));
    return t2;
  };
  auto grid_index = [&](double l) {
    return std::min(size_t(std::lower_bound(grid.begin(), grid.end(), l) - grid.begin()), n_grid - 1);
  };
  std::vector<double> out(n);
  if (!local) {
    std::vector<double> T2(n_grid);
    for (size_t g = 0; g < n_grid; ++g) T2[g] = T2_at(T.data(), g);
    for (size_t e = 0; e < n; ++e) out[e] = T2[grid_index(len[e])];
    return out;
  }
  // Start vertices in cells of size R + 1.5 l_hi: a point within R + l_e of
  // the edge is within R + 1.5 l_e of its nearer end (every point of the
  // edge is within l_e/2 of one), so it lies in the 3 x 3 cells around that end.
  const double cell = reach + 1.5 * l_hi;
  struct Entry {
    int64_t key;
    size_t k;  // start vertex (index into first)
  };
  auto key_of = [&](double px, double py) {
    const int64_t ix = int64_t(std::floor(px / cell)), iy = int64_t(std::floor(py / cell));
    return (ix + (int64_t(1) << 31)) * (int64_t(1) << 32) + (iy + (int64_t(1) << 31));
  };
  std::vector<Entry> cells(n_vert);
  for (size_t k = 0; k < n_vert; ++k) {
    const int32_t node = ends[first[k]].node;
    cells[k] = {key_of(x[node], y[node]), k};
  }
  std::sort(cells.begin(), cells.end(),
            [](const Entry& a, const Entry& b) { return a.key != b.key ? a.key < b.key : a.k < b.k; });
  std::vector<double> Tl(n_grid);
  std::vector<int64_t> seen;
  for (size_t e = 0; e < n; ++e) {
    const size_t ge = grid_index(len[e]);
    std::fill(Tl.begin(), Tl.begin() + ge + 1, 0.0);
    const double ax = x[ea[e]], ay = y[ea[e]], bx = x[eb[e]], by = y[eb[e]];
    const double r = reach + len[e];
    const double ex = bx - ax, ey = by - ay, ll = ex * ex + ey * ey;
    seen.clear();
    for (int end = 0; end < 2; ++end) {
      const double px = end ? bx : ax, py = end ? by : ay;
      for (int dx = -1; dx <= 1; ++dx)
        for (int dy = -1; dy <= 1; ++dy) {
          const int64_t key = key_of(px + dx * cell, py + dy * cell);
          if (std::find(seen.begin(), seen.end(), key) != seen.end()) continue;
          seen.push_back(key);
          auto it = std::lower_bound(cells.begin(), cells.end(), key,
                                     [](const Entry& a, int64_t kk) { return a.key < kk; });
          for (; it != cells.end() && it->key == key; ++it) {
            const End& v = ends[first[it->k]];
            if (v.body == ebody[e]) continue;  // a body does not touch itself
            // distance from the vertex to the segment
            double u = ll > 0.0 ? ((x[v.node] - ax) * ex + (y[v.node] - ay) * ey) / ll : 0.0;
            u = std::min(1.0, std::max(0.0, u));
            const double qx = ax + u * ex - x[v.node], qy = ay + u * ey - y[v.node];
            if (qx * qx + qy * qy > r * r) continue;
            const double* Wv = W.data() + it->k * n_grid;
            for (size_t g = 0; g <= ge; ++g) Tl[g] = std::max(Tl[g], Wv[g]);
          }
        }
    }
    out[e] = T2_at(Tl.data(), ge);
  }
  return out;
}

double triangle_area(const ContactInput& in, const int32_t* v) {
  return 0.5 * std::fabs((in.x[v[1]] - in.x[v[0]]) * (in.y[v[2]] - in.y[v[0]]) -
                         (in.x[v[2]] - in.x[v[0]]) * (in.y[v[1]] - in.y[v[0]]));
}

// Per node, the area of all its triangles, summed in triangle order.
std::vector<double> node_areas(const ContactInput& in) {
  std::vector<double> a(size_t(in.n_nodes), 0.0);
  for (int32_t t = 0; t < in.n_tri; ++t) {
    const int32_t* v = in.tri + 3 * static_cast<int64_t>(t);
    const double A = triangle_area(in, v);
    for (int k = 0; k < 3; ++k) a[v[k]] += A;
  }
  return a;
}

}  // namespace

ContactStableStep contact_critical_dt(const ContactParams& p, const ContactInput& in,
                                      std::vector<double>* node_stiffness, double reach) {
  return contact_critical_dt(contact_stiffness(p, in, reach), in.mass, node_stiffness);
}

ContactStiffness contact_stiffness(const ContactParams& p, const ContactInput& in, double reach) {
  ContactStiffness out;
  // Each body on its own: an edge is a boundary edge of a body if no other
  // triangle of the same body uses it, and a node shared by several bodies
  // (a freeze-bond point of a continuous mesh) counts once per body with that
  // body's share of its mass. That is the state after the bond points split,
  // so a step chosen before the run stays stable through every split. Without
  // shared nodes this is the plain per-node estimate.
  // Every figure of an edge is taken in its triangle's corner order (p, q),
  // and every sum in triangle order, never in node-id order: a bond split
  // renames a node of one body and nothing else, so the result of the split
  // mesh is the one before with that (node, body) renamed, bit for bit
  // (rename_contact_shares; the model keeps the stiffness through splits).
  struct Edge {
    int32_t a, b, body, tri, k;  // end nodes (a < b), body, triangle, the side's corner opposite
  };
  std::vector<Edge> edges;
  edges.reserve(3 * static_cast<size_t>(in.n_tri));
  for (int32_t t = 0; t < in.n_tri; ++t) {
    const int32_t* v = in.tri + 3 * static_cast<int64_t>(t);
    for (int k = 0; k < 3; ++k) {
      const int32_t a = v[(k + 1) % 3], b = v[(k + 2) % 3];
      edges.push_back({std::min(a, b), std::max(a, b), in.body[t], t, k});
    }
  }
  // ascending (a, b, body, tri): a total order, so the lists below are the same whatever sorts them
  bucket_sort(edges, in.n_nodes, [](const Edge& e) { return e.a; }, [](const Edge& e, const Edge& f) {
    if (e.b != f.b) return e.b < f.b;
    return e.body != f.body ? e.body < f.body : e.tri < f.tri;
  });
  struct Share {
    int32_t node, body;
    int64_t side;  // 3 tri + corner: the order of the group's sum
    double k, area;
  };
  std::vector<Share> shares;  // (node, body) contributions, merged below
  std::vector<double> len, alt;
  std::vector<int32_t> ea, eb, ebody;
  std::vector<int64_t> eside;
  for (size_t i = 0; i < edges.size();) {
    size_t j = i + 1;
    while (j < edges.size() && edges[j].a == edges[i].a && edges[j].b == edges[i].b &&
           edges[j].body == edges[i].body)
      ++j;
    if (j == i + 1) {
      const Edge& e = edges[i];
      const int32_t* v = in.tri + 3 * static_cast<int64_t>(e.tri);
      const int32_t p = v[(e.k + 1) % 3], q = v[(e.k + 2) % 3], o = v[e.k];
      const double ex = in.x[q] - in.x[p], ey = in.y[q] - in.y[p];
      const double l = std::hypot(ex, ey);
      const double area2 = std::fabs(ex * (in.y[o] - in.y[p]) - ey * (in.x[o] - in.x[p]));
      if (l > 0.0 && area2 > 0.0) {
        len.push_back(l);
        alt.push_back(area2 / l);
        ea.push_back(p);
        eb.push_back(q);
        ebody.push_back(e.body);
        eside.push_back(3 * int64_t(e.tri) + e.k);
      }
    }
    i = j;
  }
  if (len.empty()) {
    out.node_area.assign(in.n_nodes, 0.0);
    return out;
  }
  const std::vector<double> target = target_terms(len, alt, ea, eb, ebody, in.x, in.y, reach);
  for (size_t e = 0; e < len.size(); ++e) {
    const double ke = 1.5 * p.penalty * (len[e] / alt[e] + target[e]);
    shares.push_back({ea[e], ebody[e], eside[e], ke, 0.0});
    shares.push_back({eb[e], ebody[e], eside[e], ke, 0.0});
  }
  // Mass share of each body at a node: its triangles' share of the area around
  // the node (lumped masses are 1/3 of each triangle's mass; equal densities
  // of the bodies meeting at a node are assumed, as for ice on ice).
  out.node_area = node_areas(in);
  for (int32_t t = 0; t < in.n_tri; ++t) {
    const int32_t* v = in.tri + 3 * static_cast<int64_t>(t);
    const double A = triangle_area(in, v);
    for (int k = 0; k < 3; ++k) shares.push_back({v[k], in.body[t], 3 * int64_t(t) + k, 0.0, A});
  }
  // by (node, body), a group's shares by side: an edge's stiffness and a
  // triangle's area are zero in each other's sums, so each sum is in triangle order
  bucket_sort(shares, in.n_nodes, [](const Share& s) { return s.node; }, [](const Share& a, const Share& b) {
    return a.body != b.body ? a.body < b.body : a.side < b.side;
  });
  for (size_t i = 0; i < shares.size();) {
    size_t j = i;
    double k = 0.0, area = 0.0;
    while (j < shares.size() && shares[j].node == shares[i].node && shares[j].body == shares[i].body) {
      k += shares[j].k;
      area += shares[j].area;
      ++j;
    }
    out.node.push_back(shares[i].node);
    out.body.push_back(shares[i].body);
    out.k.push_back(k);
    out.area.push_back(area);
    i = j;
  }
  return out;
}

void rename_contact_shares(ContactStiffness& s, const std::vector<ShareRename>& renames, const ContactInput& in) {
  // the entries are in ascending (node, body) order: a rename's entry is found
  // by bisection among the keys as they were, or among those renamed before it
  const std::vector<int32_t> was = s.node;
  std::vector<size_t> renamed;
  for (const ShareRename& r : renames) {
    size_t e = size_t(std::lower_bound(was.begin(), was.end(), r.node) - was.begin());
    while (e < was.size() && was[e] == r.node && !(s.node[e] == r.node && s.body[e] == r.body)) ++e;
    if (e >= was.size() || was[e] != r.node) {
      e = s.node.size();
      for (size_t k : renamed)
        if (s.node[k] == r.node && s.body[k] == r.body) e = k;
    }
    if (e == s.node.size())
      throw std::logic_error("contact stiffness: no share of body " + std::to_string(r.body) + " at node " +
                             std::to_string(r.node) + " to rename");
    s.node[e] = r.id;
    renamed.push_back(e);
  }
  std::vector<size_t> order(s.node.size());
  for (size_t e = 0; e < order.size(); ++e) order[e] = e;
  std::sort(order.begin(), order.end(), [&](size_t a, size_t b) {
    return s.node[a] != s.node[b] ? s.node[a] < s.node[b] : s.body[a] < s.body[b];
  });
  ContactStiffness out;
  for (size_t e : order) {
    out.node.push_back(s.node[e]);
    out.body.push_back(s.body[e]);
    out.k.push_back(s.k[e]);
    out.area.push_back(s.area[e]);
  }
  out.node_area = node_areas(in);
  s = std::move(out);
}

ContactStableStep contact_critical_dt(const ContactStiffness& s, const double* mass,
                                      std::vector<double>* node_stiffness) {
  if (node_stiffness) node_stiffness->assign(s.node_area.size(), 0.0);
  ContactStableStep out;
  out.dt = INFINITY;
  const std::vector<double>& node_area = s.node_area;
  for (size_t e = 0; e < s.node.size(); ++e) {
    const int32_t n = s.node[e];
    const double k = s.k[e], area = s.area[e];
    const double m = node_area[n] > 0.0 ? mass[n] * area / node_area[n] : 0.0;
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

}  // namespace engine
