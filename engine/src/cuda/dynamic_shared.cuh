// A block's dynamic shared memory (launch_kernel_shared's shared_bytes), as
// an array of T: on a GPU the launch's; on the emulation, whose blocks run one
// after another, one static buffer of the most a block may have (an H100's
// 227 KB), so a kernel that reads past what its launch asked for is not
// caught there (the launch's size is the caller's to get right).
#pragma once
#include <cuda_runtime.h>

#include <cstddef>

namespace engine {

constexpr size_t kMostDynamicShared = 227 * 1024;

template <class T>
__device__ inline T* dynamic_shared() {
#ifdef ICERUBBLE_CUDA_EMULATION
  alignas(16) static unsigned char bytes[kMostDynamicShared];
  return reinterpret_cast<T*>(bytes);
#else
  extern __shared__ __align__(16) unsigned char dynamic_shared_bytes[];
  return reinterpret_cast<T*>(dynamic_shared_bytes);
#endif
}

}  // namespace engine
