// A kernel's launch, written once for both builds of the backend: nvcc's
// kernel<<<grid, block, 0, stream>>>(args...) where a CUDA toolkit builds it,
// the emulated runtime's launch where the build emulates it on the CPU
// (cuda/emulation/cuda_runtime.h), so the same launches run in both.
#pragma once
#include <cuda_runtime.h>

namespace engine {

template <class... Params, class... Args>
inline void launch_kernel(void (*kernel)(Params...), dim3 grid, dim3 block, cudaStream_t stream, Args... args) {
#ifdef ICERUBBLE_CUDA_EMULATION
  cuda_emu::launch(stream, grid, block, [=] { kernel(args...); });
#else
  kernel<<<grid, block, 0, stream>>>(args...);
#endif
}

// The same with `shared_bytes` of dynamic shared memory a block
// (dynamic_shared.cuh; over 48 KB the kernel must have opted in,
// cudaFuncSetAttribute).
template <class... Params, class... Args>
inline void launch_kernel_shared(void (*kernel)(Params...), dim3 grid, dim3 block, size_t shared_bytes,
                                 cudaStream_t stream, Args... args) {
#ifdef ICERUBBLE_CUDA_EMULATION
  (void)shared_bytes;  // the emulation's buffer holds the most a block may ask for
  cuda_emu::launch(stream, grid, block, [=] { kernel(args...); });
#else
  kernel<<<grid, block, shared_bytes, stream>>>(args...);
#endif
}

}  // namespace engine
