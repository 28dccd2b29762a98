// The part of the CUDA runtime the GPU backend uses, emulated on the CPU:
// a build without a CUDA toolkit compiles the backend's .cu files as C++
// against this header (engine/CMakeLists.txt, ICERUBBLE_CUDA_EMULATION), so
// that the backend's own code (launches, streams, copies, barriers, the
// whole step's bookkeeping) runs and is tested where no GPU is (docs/gpu.md,
// "The emulation"). It is a test bench, not a backend: one thread, slow.
//
// What it keeps of a GPU, so that the bugs a GPU would show show here too:
// - streams are asynchronous: work on a stream runs when the host waits for
//   it (cudaStreamSynchronize, an event, cudaDeviceSynchronize, cudaFree),
//   never earlier, so a host that reads a result before waiting reads stale
//   memory, and a copy on the legacy stream (cudaMemcpy) does not wait for a
//   non-blocking stream's work;
// - device memory is out of the host's reach outside the stream's work (the
//   host touching it stops with a message saying so);
// - fresh device memory is not zero (every byte 0xff: NaN, -1);
// - a block's lanes run as fibers that meet at __syncthreads, the shared
//   arrays one per block.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <functional>

#define ICERUBBLE_CUDA_EMULATION 1

#define __global__
#define __device__
#define __host__
#define __launch_bounds__(...)
// one array per kernel: the blocks of a launch run one after another
#define __shared__ static

struct uint3 {
  unsigned int x, y, z;
};
struct dim3 {
  unsigned int x, y, z;
  constexpr dim3(unsigned int x_ = 1, unsigned int y_ = 1, unsigned int z_ = 1) : x(x_), y(y_), z(z_) {}
};

enum cudaError_t {
  cudaSuccess = 0,
  cudaErrorInvalidValue = 1,
  cudaErrorMemoryAllocation = 2,
  cudaErrorInvalidConfiguration = 9,
  cudaErrorLaunchFailure = 719,
  cudaErrorStreamCaptureUnsupported = 900,
  cudaErrorGraphExecUpdateFailure = 910,
};
typedef cudaError_t cudaError;

enum cudaMemcpyKind {
  cudaMemcpyHostToHost = 0,
  cudaMemcpyHostToDevice = 1,
  cudaMemcpyDeviceToHost = 2,
  cudaMemcpyDeviceToDevice = 3,
  cudaMemcpyDefault = 4,
};
enum cudaStreamCaptureMode {
  cudaStreamCaptureModeGlobal = 0,
  cudaStreamCaptureModeThreadLocal = 1,
  cudaStreamCaptureModeRelaxed = 2,
};
constexpr unsigned int cudaStreamNonBlocking = 0x1;

namespace cuda_emu {
struct Stream;
struct Event;
struct Graph;
}  // namespace cuda_emu
typedef cuda_emu::Stream* cudaStream_t;
typedef cuda_emu::Event* cudaEvent_t;
typedef cuda_emu::Graph* cudaGraph_t;
typedef cuda_emu::Graph* cudaGraphExec_t;

struct cudaDeviceProp {
  char name[256];
  int multiProcessorCount;
  int maxThreadsPerBlock;
  int warpSize;
  size_t totalGlobalMem;
  size_t sharedMemPerBlock;
  int major, minor;
};

namespace cuda_emu {
// the running lane's coordinates (set before each lane runs)
extern uint3 thread_idx, block_idx;
extern dim3 block_dim, grid_dim;
// kernel<<<grid, block, 0, stream>>>: `lane` runs once per lane when the
// stream's work runs
void launch(cudaStream_t stream, dim3 grid, dim3 block, std::function<void()> lane);
void syncthreads();
int syncthreads_or(int predicate);
[[noreturn]] void trap();
}  // namespace cuda_emu

#define threadIdx (::cuda_emu::thread_idx)
#define blockIdx (::cuda_emu::block_idx)
#define blockDim (::cuda_emu::block_dim)
#define gridDim (::cuda_emu::grid_dim)

inline void __syncthreads() { cuda_emu::syncthreads(); }
inline int __syncthreads_or(int predicate) { return cuda_emu::syncthreads_or(predicate); }
inline int __ffsll(long long x) { return __builtin_ffsll(x); }
// a kernel's assertion: the emulation stops with the message a GPU's launch error stands for
[[noreturn]] inline void __trap() {
  cuda_emu::trap();
  __builtin_unreachable();
}
// CUDA's isnan, unqualified in device code (friction.cu)
using std::isnan;
// the lanes run one at a time: a read-modify-write is atomic
template <class T>
inline T atomicAdd(T* a, T v) {
  const T old = *a;
  *a = old + v;
  return old;
}
template <class T>
inline T atomicMin(T* a, T v) {
  const T old = *a;
  if (v < old) *a = v;
  return old;
}
// CUDA's integer min and max
inline int max(int a, int b) { return a > b ? a : b; }
inline int min(int a, int b) { return a < b ? a : b; }
inline unsigned int max(unsigned int a, unsigned int b) { return a > b ? a : b; }
inline unsigned int min(unsigned int a, unsigned int b) { return a < b ? a : b; }
inline long long max(long long a, long long b) { return a > b ? a : b; }
inline long long min(long long a, long long b) { return a < b ? a : b; }
inline long max(long a, long b) { return a > b ? a : b; }
inline long min(long a, long b) { return a < b ? a : b; }

cudaError_t cudaGetDeviceCount(int* count);
cudaError_t cudaGetDeviceProperties(cudaDeviceProp* prop, int device);
// A block's shared memory beyond 48 KB: the device's limit (an H100's here)
// and the kernel's opt-in to it, which the emulation's static buffer
// (cuda/dynamic_shared.cuh) needs not.
enum cudaDeviceAttr { cudaDevAttrMaxSharedMemoryPerBlockOptin = 97 };
enum cudaFuncAttribute { cudaFuncAttributeMaxDynamicSharedMemorySize = 8 };
cudaError_t cudaDeviceGetAttribute(int* value, cudaDeviceAttr attr, int device);
template <class Kernel>
inline cudaError_t cudaFuncSetAttribute(Kernel, cudaFuncAttribute, int) {
  return cudaSuccess;
}
cudaError_t cudaGetLastError();
const char* cudaGetErrorString(cudaError_t e);
cudaError_t cudaDeviceSynchronize();

cudaError_t cudaMalloc(void** p, size_t bytes);
template <class T>
inline cudaError_t cudaMalloc(T** p, size_t bytes) {
  return cudaMalloc(reinterpret_cast<void**>(p), bytes);
}
cudaError_t cudaFree(void* p);
cudaError_t cudaMallocHost(void** p, size_t bytes);
template <class T>
inline cudaError_t cudaMallocHost(T** p, size_t bytes) {
  return cudaMallocHost(reinterpret_cast<void**>(p), bytes);
}
cudaError_t cudaFreeHost(void* p);
cudaError_t cudaMemcpy(void* dst, const void* src, size_t bytes, cudaMemcpyKind kind);
cudaError_t cudaMemcpyAsync(void* dst, const void* src, size_t bytes, cudaMemcpyKind kind, cudaStream_t s = nullptr);
cudaError_t cudaMemset(void* p, int value, size_t bytes);
cudaError_t cudaMemsetAsync(void* p, int value, size_t bytes, cudaStream_t s = nullptr);

cudaError_t cudaStreamCreateWithFlags(cudaStream_t* s, unsigned int flags);
cudaError_t cudaStreamDestroy(cudaStream_t s);
cudaError_t cudaStreamSynchronize(cudaStream_t s);

cudaError_t cudaEventCreate(cudaEvent_t* e);
cudaError_t cudaEventDestroy(cudaEvent_t e);
cudaError_t cudaEventRecord(cudaEvent_t e, cudaStream_t s = nullptr);
cudaError_t cudaEventSynchronize(cudaEvent_t e);
cudaError_t cudaEventElapsedTime(float* ms, cudaEvent_t a, cudaEvent_t b);

cudaError_t cudaStreamBeginCapture(cudaStream_t s, cudaStreamCaptureMode mode);
cudaError_t cudaStreamEndCapture(cudaStream_t s, cudaGraph_t* g);
cudaError_t cudaGraphInstantiate(cudaGraphExec_t* exec, cudaGraph_t g, unsigned long long flags = 0);
cudaError_t cudaGraphLaunch(cudaGraphExec_t exec, cudaStream_t s);
cudaError_t cudaGraphDestroy(cudaGraph_t g);
cudaError_t cudaGraphExecDestroy(cudaGraphExec_t exec);
// CUDA 12's form; the emulation fills `result` only (0: updated)
struct cudaGraphExecUpdateResultInfo {
  int result;
  void* errorNode;
  void* errorFromNode;
};
cudaError_t cudaGraphExecUpdate(cudaGraphExec_t exec, cudaGraph_t g, cudaGraphExecUpdateResultInfo* info);
