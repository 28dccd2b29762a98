#include "contact/broad_phase.hpp"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace engine {

constexpr int32_t kMinParallelSurface = 4096;

void BroadPhase::find(int32_t n_surface, const int32_t* surface_tris, const int32_t* tri,
                      const int32_t* body, const double* x, const double* y,
                      std::vector<CandidatePair>& pairs, int threads, double skin_fraction) {
  pairs.clear();
  skin_ = 0.0;
  const int32_t n = n_surface;
  if (n < 2) return;
  bx0_.resize(n);
  by0_.resize(n);
  bx1_.resize(n);
  by1_.resize(n);
  cell_of_.resize(n);
  sorted_.resize(n);

  double ext = 0.0, xmin = INFINITY, ymin = INFINITY, xmax = -INFINITY, ymax = -INFINITY;
  for (int32_t i = 0; i < n; ++i) {
    const int32_t* v = tri + 3 * static_cast<int64_t>(surface_tris[i]);
    const double x0 = x[v[0]], x1 = x[v[1]], x2 = x[v[2]];
    const double y0 = y[v[0]], y1 = y[v[1]], y2 = y[v[2]];
    const double lx = std::min(x0, std::min(x1, x2)), ux = std::max(x0, std::max(x1, x2));
    const double ly = std::min(y0, std::min(y1, y2)), uy = std::max(y0, std::max(y1, y2));
    // the corners themselves: std::min and std::max can pass a NaN over
    if (!(std::isfinite(x0) && std::isfinite(x1) && std::isfinite(x2) && std::isfinite(y0) && std::isfinite(y1) &&
          std::isfinite(y2)))
      throw std::runtime_error("contact detection: non-finite node position in triangle " +
                               std::to_string(surface_tris[i]));
    bx0_[i] = lx;
    bx1_[i] = ux;
    by0_[i] = ly;
    by1_[i] = uy;
    ext = std::max(ext, std::max(ux - lx, uy - ly));
    xmin = std::min(xmin, lx);
    ymin = std::min(ymin, ly);
    xmax = std::max(xmax, lx);
    ymax = std::max(ymax, ly);
  }
  // Grow every box by the skin; the cells must hold the grown boxes.
  const GridShape g = grid_shape(n, ext, xmin, ymin, xmax, ymax, skin_fraction);
  skin_ = g.skin;
  for (int32_t i = 0; i < n; ++i) {
    bx0_[i] -= skin_;
    by0_[i] -= skin_;
    bx1_[i] += skin_;
    by1_[i] += skin_;
  }
  const int64_t nx = g.nx, ny = g.ny;
  cell_ = g.h;
  const int64_t ncell = nx * ny;

  // Counting sort of the triangles by cell (stable: input order within a cell).
  cell_start_.assign(ncell + 1, 0);
  for (int32_t i = 0; i < n; ++i) {
    cell_of_[i] = static_cast<int32_t>(engine::cell_of(g, bx0_[i], by0_[i]));
    ++cell_start_[cell_of_[i] + 1];
  }
  for (int64_t c = 0; c < ncell; ++c) cell_start_[c + 1] += cell_start_[c];
  cursor_.assign(cell_start_.begin(), cell_start_.end() - 1);
  for (int32_t i = 0; i < n; ++i) sorted_[cursor_[cell_of_[i]]++] = i;

  // Waking threads costs more than scanning a few thousand triangles, and on a
  // busy machine a lot more.
  const int nthreads = n < kMinParallelSurface ? 1 : (threads > 0 ? threads : omp_get_max_threads());
  if (static_cast<int>(per_thread_.size()) < nthreads) per_thread_.resize(nthreads);

#pragma omp parallel num_threads(nthreads) if (nthreads > 1)
  {
    std::vector<CandidatePair>& out = per_thread_[omp_get_thread_num()];
    out.clear();
    // Tests one pair of surface-list entries and records it if it qualifies.
    auto test = [&](int32_t i, int32_t j) {
      const double bi[4] = {bx0_[i], by0_[i], bx1_[i], by1_[i]}, bj[4] = {bx0_[j], by0_[j], bx1_[j], by1_[j]};
      const int32_t ta = surface_tris[i], tb = surface_tris[j];
      if (!candidate_pair(bi, bj, ta, tb, tri, body)) return;
      out.push_back(ta < tb ? CandidatePair{ta, tb} : CandidatePair{tb, ta});
    };
#pragma omp for schedule(static)
    for (int64_t iy = 0; iy < ny; ++iy) {
      for (int64_t ix = 0; ix < nx; ++ix) {
        const int64_t c = iy * nx + ix;
        const int32_t b0 = cell_start_[c], b1 = cell_start_[c + 1];
        if (b0 == b1) continue;
        for (int32_t p = b0; p < b1; ++p)
          for (int32_t q = p + 1; q < b1; ++q) test(sorted_[p], sorted_[q]);
        int64_t nb[4][2];
        forward_neighbours(ix, iy, nb);
        for (const auto& d : nb) {
          if (d[0] < 0 || d[0] >= nx || d[1] >= ny) continue;
          const int64_t cn = d[1] * nx + d[0];
          for (int32_t p = b0; p < b1; ++p)
            for (int32_t q = cell_start_[cn]; q < cell_start_[cn + 1]; ++q)
              test(sorted_[p], sorted_[q]);
        }
      }
    }
  }
  // Static schedule: thread k holds a contiguous block of rows after thread
  // k-1's, so concatenating in thread order gives the serial order.
  for (int t = 0; t < nthreads; ++t)
    pairs.insert(pairs.end(), per_thread_[t].begin(), per_thread_[t].end());
}

}  // namespace engine
