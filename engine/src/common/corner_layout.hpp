// Where a corner's loads (CornerLoad's fields) live, for the kernels both
// backends share: the CPU keeps each corner's fields together (one cache line
// per corner in its gather), the GPU one array per field, so that a warp's 32
// triangles write and read consecutive addresses (coalesced; the interleaved
// records made the GPU's triangle pass 2.3 times as slow; docs/gpu.md).
#pragma once
#include <cstddef>

#include "common/host_device.hpp"
#include "common/mesh_arrays.hpp"

namespace engine {

// Triangles::corner_load: CornerLoad::stride doubles per corner slot 3*t+k.
struct CornerRecords {
  double* base;
  ICERUBBLE_HD double& operator()(size_t slot, int field) const { return base[slot * CornerLoad::stride + field]; }
};

// CornerLoad::stride arrays of n_slots doubles, field after field.
struct CornerFields {
  double* base;
  size_t n_slots;
  ICERUBBLE_HD double& operator()(size_t slot, int field) const { return base[field * n_slots + slot]; }
};

}  // namespace engine
