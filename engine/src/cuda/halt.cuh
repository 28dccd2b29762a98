// The halt word of a batch of whole steps (cuda/device_step.cu). A batch
// launches several steps before the host reads any of them back; a step that
// ends in an event the host must handle (a bond point at the criterion, a
// candidate list to rebuild, a node past reach/2, an element
// inverted, a sum not finite) sets the word, and every later kernel of the
// batch returns at once, so the GPU's state stays the one that step left.
// The word changes only between kernels, so a block reads one value: the
// return is the whole block's, before any barrier. A stage run on its own
// (the comparisons of docs/gpu.md) passes none.
#pragma once
#include <cuda_runtime.h>

#include <cstdint>

namespace engine {

__device__ inline bool halted(const int32_t* halt) { return halt != nullptr && *halt != 0; }

}  // namespace engine
