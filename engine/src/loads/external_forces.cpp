#include "loads/external_forces.hpp"

#include <algorithm>

#include "common/parameter_range.hpp"
#include "engine_parameter_ranges.hpp"
#include "loads/drag_kernel.hpp"

namespace engine {

namespace {

constexpr bool same_name(const char* a, const char* b) {
  while (*a != '\0' && *a == *b) ++a, ++b;
  return *a == *b;
}

template <size_t N, size_t M>
constexpr bool same_names(const char* const (&a)[N], const char* const (&b)[M]) {
  if (N != M) return false;
  for (size_t i = 0; i < N; ++i) {
    bool found = false;
    for (size_t j = 0; j < M; ++j) found = found || same_name(a[i], b[j]);
    if (!found) return false;
  }
  return true;
}

static_assert(same_names(kDragModelNames, registry::drag_model_choices),
              "DragModel's names and the registry's drag_model choices (icerubble/parameters.py) differ");

}  // namespace

DragModel drag_model_named(const std::string& name) {
  const auto m = std::find(std::begin(kDragModelNames), std::end(kDragModelNames), name);
  if (m == std::end(kDragModelNames))
    bad("parameter drag_model='" + name + "' is invalid: valid values are " + registry::drag_model_range);
  return DragModel(m - std::begin(kDragModelNames));
}

void validate(const ExternalParams& p) {
  check(registry::g, p.g);
  check(registry::rho_w, p.rho_w);
  check(registry::y_w, p.y_w);
  check(registry::c_w, p.c_w);
  check(registry::C_d, p.C_d);
  const int d = int(p.drag_model);
  if (d < int(DragModel::None) || d > int(DragModel::Quadratic))
    bad(std::string("drag_model is invalid: valid values are ") + registry::drag_model_range);
}

WaterArrays water_arrays(const Nodes& nodes, Triangles& tris, const ExternalParams& p,
                         const std::vector<double>& body_area0, const std::vector<double>& body_drag) {
  return {nodes.x.data(), nodes.y.data(), tris.node.data(), tris.body.data(), tris.area0.data(),
          body_area0.data(), body_drag.data(), p.y_w, p.rho_w * p.g,
          p.buoyancy, p.drag_on()};
}

double water_forces_on_triangles(const Nodes& nodes, Triangles& tris, const ExternalParams& p,
                                 const std::vector<double>& body_area0,
                                 const std::vector<double>& body_drag, int32_t begin, int32_t end,
                                 const int32_t* list) {
  const WaterArrays a = water_arrays(nodes, tris, p, body_area0, body_drag);
  double submerged = 0.0;
  const CornerRecords load{tris.corner_load.data()};
  for (int32_t k = begin; k < end; ++k) submerged += water_triangle(a, load, list ? list[k] : k);
  return submerged;
}

void BodyTriangleLists::build(const Triangles& tris, const std::vector<int32_t>& surface, int32_t n_bodies,
                              int32_t n_nodes) {
  // rows by body of the triangles ids[0, n) (all triangles where ids is null)
  const auto rows = [&](const int32_t* ids, int32_t n, std::vector<int32_t>& first, std::vector<int32_t>& out) {
    first.assign(size_t(n_bodies) + 1, 0);
    for (int32_t k = 0; k < n; ++k) ++first[tris.body[ids ? ids[k] : k] + 1];
    for (int32_t b = 0; b < n_bodies; ++b) first[b + 1] += first[b];
    out.resize(n);
    std::vector<int32_t> fill(first.begin(), first.end() - 1);
    for (int32_t k = 0; k < n; ++k) {
      const int32_t t = ids ? ids[k] : k;
      out[fill[tris.body[t]]++] = t;
    }
  };
  std::vector<int32_t> tri, surface_start_tri, surface_tri;
  rows(nullptr, tris.size(), start, tri);
  corner.resize(size_t(3) * tri.size());
  weight.resize(tri.size());
  for (size_t k = 0; k < tri.size(); ++k) {
    const int32_t t = tri[k];
    for (int c = 0; c < 3; ++c) corner[3 * k + c] = tris.node[3 * size_t(t) + c];
    weight[k] = tris.area0[t] / 3.0;  // the division the sums did per triangle: the same bits
  }
  rows(surface.data(), int32_t(surface.size()), surface_start_tri, surface_tri);
  // each body's surface points once (a node of two bodies, a bond point, in both)
  std::vector<int32_t> seen(size_t(n_nodes), -1);
  surface_start.assign(size_t(n_bodies) + 1, 0);
  surface_node.clear();
  for (int32_t b = 0; b < n_bodies; ++b) {
    for (int32_t k = surface_start_tri[b]; k < surface_start_tri[b + 1]; ++k)
      for (int c = 0; c < 3; ++c) {
        const int32_t i = tris.node[3 * size_t(surface_tri[k]) + c];
        if (seen[i] == b) continue;
        seen[i] = b;
        surface_node.push_back(i);
      }
    surface_start[b + 1] = int32_t(surface_node.size());
  }
  largest_first.resize(size_t(n_bodies));
  for (int32_t b = 0; b < n_bodies; ++b) largest_first[b] = b;
  std::stable_sort(largest_first.begin(), largest_first.end(),
                   [&](int32_t a, int32_t b) { return start[a + 1] - start[a] > start[b + 1] - start[b]; });
}

size_t BodyTriangleLists::bytes() const {
  return (start.capacity() + corner.capacity() + surface_start.capacity() + surface_node.capacity() +
          largest_first.capacity()) * sizeof(int32_t) + weight.capacity() * sizeof(double);
}

void body_drag_constants(const Nodes& nodes, const ExternalParams& p,
                         const std::vector<double>& body_area0, std::vector<double>& body_drag,
                         const BodyTriangleLists& lists, int threads) {
  const int32_t nb = int32_t(body_area0.size());
  body_drag.assign(nb, 0.0);
  if (!p.drag_on()) return;
  if (p.drag_model == DragModel::Linear) {
    std::fill(body_drag.begin(), body_drag.end(), p.c_w);
    return;
  }
  const BodyDragArrays a{nodes.x.data(),        nodes.y.data(),          nodes.vx.data(),
                         nodes.vy.data(),       body_area0.data(),       lists.start.data(),
                         lists.corner.data(),   lists.weight.data(),     lists.surface_start.data(),
                         lists.surface_node.data(), 0.5 * p.rho_w * p.C_d};
  double* c_b = body_drag.data();
  const int32_t* order = lists.largest_first.data();
  // dynamic, largest bodies first: the layer's bodies are far larger than a block
  #pragma omp parallel for schedule(dynamic, 1) num_threads(threads) if (threads > 1)
  for (int32_t k = 0; k < nb; ++k) c_b[order[k]] = quadratic_drag_constant(a, order[k]);
}

}  // namespace engine
