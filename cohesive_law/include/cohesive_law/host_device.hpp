// The cohesive law's functions are compiled for the GPU too where nvcc
// includes them (the engine's bond check and cohesive forces, docs/gpu.md):
// __host__ __device__ there, plain inline functions otherwise. Their math
// calls are unqualified (sqrt, hypot, fabs: the C library's on the host,
// CUDA's on the device), so the same source compiles for both.
#pragma once

#if defined(__CUDACC__)
#define COHESIVE_LAW_HD __host__ __device__ inline
#else
#define COHESIVE_LAW_HD inline
#endif
