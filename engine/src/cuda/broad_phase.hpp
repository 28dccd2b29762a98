// The contact candidate list searched on the GPU (docs/gpu.md, "The
// candidate list on the GPU"): BroadPhase::find's search (the same cell grid,
// grid_shape; the same pair test, candidate_pair) and lay_out_candidates'
// layout, made from the positions on the GPU, so that a whole step rebuilds
// its list without the positions leaving the GPU. A plain C++ header (no
// CUDA types); in a build without CUDA every call says so.
#pragma once
#include <cstdint>
#include <memory>
#include <vector>

namespace engine {

class Model;

// A candidate layout read back from the GPU (contact/candidate_layout.hpp's
// arrays but the triangles), for comparison with the CPU's.
struct SearchedLayout {
  std::vector<int32_t> node, start, entry;
  std::vector<uint64_t> key;
  double skin = 0.0;
};

class DeviceBroadPhase {
 public:
  // The model's surface triangles, their nodes and bodies, and the skin
  // fraction of its contact solver, copied to the GPU.
  explicit DeviceBroadPhase(const Model& model);
  ~DeviceBroadPhase();
  DeviceBroadPhase(const DeviceBroadPhase&) = delete;
  DeviceBroadPhase& operator=(const DeviceBroadPhase&) = delete;

  // The search at the model's positions (copied to the GPU), its layout read
  // back. Throws std::runtime_error on a non-finite position, as the CPU's.
  SearchedLayout search(const Model& model);
  // Mean wall time of a search at the model's positions (copied once), its
  // wait for the count included, over `repeats` searches after one [s].
  double seconds_per_search(const Model& model, int repeats);

 private:
  friend class DeviceStep;  // the whole step searches at its own positions (cuda/device_step.cu)
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace engine
