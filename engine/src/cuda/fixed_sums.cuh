// Reductions over a block in a fixed tree: every run gives the same bits
// (no atomics in any sum of the GPU backend; docs/gpu.md).
#pragma once
#include <cuda_runtime.h>

namespace engine {

// Sums in a fixed tree over a block's N lanes (N a power of two; every lane
// calls it): every run gives the same bits, no atomics in any sum.
template <int N>
__device__ inline double block_sum(double v, double* shared) {
  shared[threadIdx.x] = v;
  __syncthreads();
  for (int w = N / 2; w > 0; w /= 2) {
    if (int(threadIdx.x) < w) shared[threadIdx.x] += shared[threadIdx.x + w];
    __syncthreads();
  }
  const double total = shared[0];
  __syncthreads();  // the buffer is free again
  return total;
}

template <int N, bool kMax>
__device__ inline double block_extreme(double v, double* shared) {
  shared[threadIdx.x] = v;
  __syncthreads();
  for (int w = N / 2; w > 0; w /= 2) {
    if (int(threadIdx.x) < w) {
      const double o = shared[threadIdx.x + w];
      if (kMax ? o > shared[threadIdx.x] : o < shared[threadIdx.x]) shared[threadIdx.x] = o;
    }
    __syncthreads();
  }
  const double e = shared[0];
  __syncthreads();
  return e;
}

}  // namespace engine
