// Broad phase of the contact search (docs/model.md §3: step (2), neighbour search).
//
// A uniform cell grid with cells at least as large as the largest bounding box
// of a surface triangle. Each triangle is binned by the lower-left corner of its
// bounding box, so two triangles whose boxes overlap sit in the same or in
// adjacent cells, and scanning each cell against itself and four forward
// neighbours visits every such pair exactly once. The cost is linear in the
// number of surface triangles (the grid is capped at a few cells per triangle,
// coarsening the cells when the triangles are spread over a large area).
// Boxes can be grown by a skin so that the list can be reused over many steps
// (a Verlet list): detection then costs a displacement check per step.
#pragma once
#include <cmath>
#include <cstdint>
#include <vector>

#include "common/host_device.hpp"

namespace engine {

// Whether a node at (x, y) has moved past the skin from (x0, y0), where the
// candidate list was built: the list is then rebuilt (ContactSolver on the
// CPU, the GPU step on the GPU). Written so that a NaN position moves.
ICERUBBLE_HD bool moved_past_skin(double x, double y, double x0, double y0, double skin) {
  return !(fabs(x - x0) <= skin && fabs(y - y0) <= skin);
}

struct CandidatePair {
  int32_t a;  // triangle id, a < b; a acts as the contactor
  int32_t b;
};

// The cell grid of a search, from the surface triangles' bounding boxes
// (before the skin): the largest extent of a box, the smallest lower-left
// corners and the largest ones. Both backends' searches size it here
// (BroadPhase::find on the CPU, cuda/broad_phase.cu on the GPU), so both bin
// the triangles alike.
struct GridShape {
  double skin = 0.0;            // the boxes are grown by this [m]
  double xmin = 0.0, ymin = 0.0;  // the grid's origin (the grown boxes' lower-left corners)
  double h = 1.0;               // the cell size [m]
  int64_t nx = 1, ny = 1;
};

// `n` surface triangles; ext, xmin, ymin the largest box extent and smallest
// lower-left corner, xmax, ymax the largest lower-left corner. Cells slightly
// larger than the largest grown box (rounding in the binning never puts two
// overlapping boxes two cells apart), coarsened until the grid has at most
// 4 n + 64 cells (max_cells).
ICERUBBLE_HD int64_t max_cells(int64_t n) { return 4 * n + 64; }
ICERUBBLE_HD GridShape grid_shape(int64_t n, double ext, double xmin, double ymin, double xmax, double ymax,
                                  double skin_fraction) {
  GridShape g;
  g.skin = skin_fraction * ext;
  g.xmin = xmin - g.skin;
  g.ymin = ymin - g.skin;
  xmax -= g.skin;
  ymax -= g.skin;
  ext += 2.0 * g.skin;
  double h = ext > 0.0 ? ext * (1.0 + 1e-9) : 1.0;
  const double cap = double(max_cells(n));
  for (;;) {
    g.nx = static_cast<int64_t>(floor((xmax - g.xmin) / h)) + 1;
    g.ny = static_cast<int64_t>(floor((ymax - g.ymin) / h)) + 1;
    const double cells = static_cast<double>(g.nx) * static_cast<double>(g.ny);
    if (cells <= cap) break;
    const double grow = sqrt(cells / cap);
    h *= grow > 1.01 ? grow : 1.01;
  }
  g.h = h;
  return g;
}

// The cell of a grown box with lower-left corner (x0, y0): its column and
// row, the last where past the grid (a corner within it is never below its
// origin; a NaN one, which the search reports, falls in the first).
ICERUBBLE_HD int64_t grid_index(double at, double origin, double h, int64_t n) {
  const double f = (at - origin) / h;
  if (!(f >= 0.0)) return 0;
  if (!(f < static_cast<double>(n - 1))) return n - 1;
  return static_cast<int64_t>(f);
}
ICERUBBLE_HD int64_t cell_of(const GridShape& g, double x0, double y0) {
  return grid_index(y0, g.ymin, g.h, g.ny) * g.nx + grid_index(x0, g.xmin, g.h, g.nx);
}

// Whether surface triangles ta and tb (grown boxes b0 = {x0, y0, x1, y1})
// make a candidate: the boxes overlap (closed), the bodies differ and the
// triangles share no node (elements sharing a node never contact).
ICERUBBLE_HD bool candidate_pair(const double* ba, const double* bb, int32_t ta, int32_t tb, const int32_t* tri,
                                 const int32_t* body) {
  if (ba[0] > bb[2] || bb[0] > ba[2] || ba[1] > bb[3] || bb[1] > ba[3]) return false;
  if (body[ta] == body[tb]) return false;
  const int32_t* va = tri + 3 * static_cast<int64_t>(ta);
  const int32_t* vb = tri + 3 * static_cast<int64_t>(tb);
  for (int p = 0; p < 3; ++p)
    for (int q = 0; q < 3; ++q)
      if (va[p] == vb[q]) return false;
  return true;
}

// The forward neighbours of a cell a search visits after the cell itself:
// east, north-west, north, north-east (each pair of cells once).
ICERUBBLE_HD void forward_neighbours(int64_t ix, int64_t iy, int64_t nb[4][2]) {
  nb[0][0] = ix + 1; nb[0][1] = iy;
  nb[1][0] = ix - 1; nb[1][1] = iy + 1;
  nb[2][0] = ix;     nb[2][1] = iy + 1;
  nb[3][0] = ix + 1; nb[3][1] = iy + 1;
}

class BroadPhase {
 public:
  // Replaces `pairs` with every pair of triangles from surface_tris that belong
  // to different bodies, share no node, and whose closed bounding boxes, each
  // grown by the skin on every side, overlap. The skin is skin_fraction times
  // the largest box extent; the list then stays complete until some node has
  // moved by more than the skin in x or y (ContactSolver reuses it until then).
  // The order is deterministic (cell by cell, then input order) and does not
  // depend on the number of threads. Throws std::runtime_error on a non-finite
  // node position. threads: OpenMP threads (0: OpenMP default); small problems
  // run serially.
  void find(int32_t n_surface, const int32_t* surface_tris, const int32_t* tri,
            const int32_t* body, const double* x, const double* y,
            std::vector<CandidatePair>& pairs, int threads = 0, double skin_fraction = 0.0);

  double cell_size() const { return cell_; }
  double skin() const { return skin_; }  // of the last find [m]

 private:
  // Buffers kept between steps so that a step allocates nothing.
  std::vector<double> bx0_, by0_, bx1_, by1_;  // bounding boxes, per surface triangle
  std::vector<int32_t> cell_of_, cell_start_, cursor_, sorted_;
  std::vector<std::vector<CandidatePair>> per_thread_;
  double cell_ = 0.0;
  double skin_ = 0.0;
};

}  // namespace engine
