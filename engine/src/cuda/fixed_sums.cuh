// Reductions over a block in a fixed tree: every run gives the same bits
// (no atomics in any sum of the GPU backend; docs/gpu.md).
#pragma once
#include <cuda_runtime.h>

#include <cstdint>

#include "cuda/halt.cuh"

namespace engine {

// The lanes of a block that reduces with barriers: `on_gpu` on a GPU. The
// CPU emulation (cuda/emulation/) runs a block's lanes as fibers, switched at
// every barrier of the tree (a sum over 1024 lanes: 11 rounds of 1024
// switches): there the same kernels run with at most 32 lanes, the same
// trees a few levels shorter (a block's fibers' frames then stay in the
// core's first cache), so its sums add in another fixed order (to
// round-off) and nothing else changes (friction's colours are fixed by the
// candidates' priorities, not by the lanes).
constexpr int reducing_block(int on_gpu) {
#ifdef ICERUBBLE_CUDA_EMULATION
  return on_gpu < 32 ? on_gpu : 32;
#else
  return on_gpu;
#endif
}
// The lanes of a block that runs alone over a whole array: the final sums,
// friction's colouring and sweeps.
constexpr int kWideBlock = reducing_block(1024);

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

// Each lane's inclusive prefix sum of v over a block's N lanes (Hillis-Steele;
// every lane calls it): integer counts, so any order gives the same result.
template <int N>
__device__ inline int32_t block_inclusive_scan(int32_t v, int32_t* shared) {
  shared[threadIdx.x] = v;
  __syncthreads();
  for (int w = 1; w < N; w *= 2) {
    const int32_t add = int(threadIdx.x) >= w ? shared[threadIdx.x - w] : 0;
    __syncthreads();
    shared[threadIdx.x] += add;
    __syncthreads();
  }
  const int32_t s = shared[threadIdx.x];
  __syncthreads();  // the buffer is free again
  return s;
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

// a[0, n) added by a block's N lanes in a fixed order: each lane its terms
// l, l + N, ... in order, then the block's tree (every lane calls it). The
// second level of the per-block trees above: every final sum of the backend.
template <int N>
__device__ inline double strided_block_sum(const double* a, int64_t n, double* shared) {
  double s = 0.0;
  for (int64_t k = threadIdx.x; k < n; k += N) s += a[k];
  return block_sum<N>(s, shared);
}

// Term k's per-block partial sums, partial[k * n_blocks + b], added by one
// block of N lanes per term (launch with as many blocks as terms): sums[k].
template <int N>
__global__ void __launch_bounds__(N) term_sums_kernel(const int32_t* halt, const double* partial, int32_t n_blocks,
                                                      double* sums) {
  if (halted(halt)) return;
  __shared__ double shared[N];
  const double s = strided_block_sum<N>(partial + size_t(blockIdx.x) * n_blocks, n_blocks, shared);
  if (threadIdx.x == 0) sums[blockIdx.x] = s;
}

// Sums of the form above in one launch, a block each: job b's a[0, n) into
// *out (strided_block_sum, as each stage's own sum adds them, so the same
// bits): the whole step (cuda/device_step.cu) sums its stages' partials in
// one launch instead of one per stage.
struct SumJob {
  const double* a;
  int64_t n;
  double* out;
};
constexpr int kMaxSumJobs = 32;
struct SumJobs {
  SumJob job[kMaxSumJobs];
  int32_t n = 0;
  void add(const double* a, int64_t n_terms, double* out) { job[n++] = SumJob{a, n_terms, out}; }
};

template <int N>
__global__ void __launch_bounds__(N) sum_jobs_kernel(const int32_t* halt, SumJobs jobs) {
  if (halted(halt)) return;
  __shared__ double shared[N];
  const SumJob j = jobs.job[blockIdx.x];
  const double s = strided_block_sum<N>(j.a, j.n, shared);
  if (threadIdx.x == 0) *j.out = s;
}

}  // namespace engine
