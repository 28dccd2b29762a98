// The GPU broad phase's state (cuda/broad_phase.cu), where the whole step
// (cuda/device_step.cu) can reach it.
#pragma once
#include "contact/broad_phase.hpp"
#include "cuda/broad_phase.hpp"
#include "cuda/device_array.cuh"

namespace engine {

// Where a search writes its layout (contact/candidate_layout.hpp's arrays):
// sized by the search.
struct LayoutArrays {
  DeviceArray<int32_t>* node;   // 6 per candidate
  DeviceArray<uint64_t>* key;   // friction_pair_key per candidate, ascending
  DeviceArray<int32_t>* start;  // n_nodes + 1
  DeviceArray<int32_t>* entry;  // 6 per candidate, each node's in candidate order
};

struct DeviceBroadPhase::Impl {
  int32_t n_surface = 0, n_nodes = 0, n_tri = 0;
  double skin_fraction = 0.0;
  DeviceArray<int32_t> surface, tri, body;
  // per surface triangle: its box (grown by the skin after the grid is
  // known), its cell and index, sorted by cell; per sorted triangle its
  // candidates' count and first slot
  DeviceArray<double> bx0, by0, bx1, by1, partial;
  DeviceArray<GridShape> grid;
  DeviceArray<uint32_t> cell, cell_sorted;
  DeviceArray<int32_t> index, sorted, cell_start, counts, offsets, first_bad;
  DeviceArray<uint64_t> pairs, pairs_sorted;
  DeviceArray<uint32_t> entry_node, entry_node_sorted;
  DeviceArray<int32_t> entry_id;
  DeviceArray<uint8_t> scratch;
  int32_t* host_found = nullptr;  // pinned: the candidates' count, the first non-finite triangle
  GridShape* host_grid = nullptr;  // pinned
  cudaStream_t stream = nullptr;

  // The search at positions x, y (GPU memory, n_nodes each) on `stream`,
  // laid out into `out`: returns the number of candidates, `skin` the
  // boxes' skin. Waits once, for the count that sizes the outputs.
  int32_t search(const double* x, const double* y, const LayoutArrays& out, double& skin);
  void upload_positions(const Model& m, DeviceArray<double>& x, DeviceArray<double>& y);
};

}  // namespace engine
