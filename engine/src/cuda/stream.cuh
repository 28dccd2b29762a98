// A stream on the visible GPU, and the mean time of a launch on it: what
// every stage of the backend needs around its own kernels.
#pragma once
#include <cuda_runtime.h>

#include <stdexcept>

#include "cuda/device_array.cuh"

namespace engine {

// A non-blocking stream; says so when no GPU is visible.
inline cudaStream_t new_stream() {
  int count = 0;
  if (cudaGetDeviceCount(&count) != cudaSuccess || count == 0) {
    cudaGetLastError();  // clear it
    throw std::runtime_error("GPU: no CUDA device is visible");
  }
  cudaStream_t s = nullptr;
  cuda_check(cudaStreamCreateWithFlags(&s, cudaStreamNonBlocking), "cudaStreamCreate");
  return s;
}

// Mean wall time of launch() on `stream` over `repeats` calls after three
// warm-up calls [s], from device events.
template <class Launch>
double mean_launch_seconds(cudaStream_t stream, int repeats, Launch launch) {
  if (repeats < 1) throw std::invalid_argument("repeats must be at least 1");
  for (int k = 0; k < 3; ++k) launch();
  cudaEvent_t a, b;
  cuda_check(cudaEventCreate(&a), "event");
  cuda_check(cudaEventCreate(&b), "event");
  cuda_check(cudaEventRecord(a, stream), "event");
  for (int k = 0; k < repeats; ++k) launch();
  cuda_check(cudaEventRecord(b, stream), "event");
  cuda_check(cudaEventSynchronize(b), "event");
  float ms = 0.0f;
  cuda_check(cudaEventElapsedTime(&ms, a, b), "event");
  cudaEventDestroy(a);
  cudaEventDestroy(b);
  return 1e-3 * double(ms) / repeats;
}

}  // namespace engine
