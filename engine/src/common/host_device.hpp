// Marks the per-element, per-node and per-body physics that both backends
// compile: __host__ __device__ under nvcc, plain inline functions in the CPU
// build, so the CPU build (and CI, which has no GPU) runs the very code the
// GPU runs (docs/gpu.md).
#pragma once

#if defined(__CUDACC__)
#define ICERUBBLE_HD __host__ __device__ inline
#else
#define ICERUBBLE_HD inline
#endif
