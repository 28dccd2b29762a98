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
