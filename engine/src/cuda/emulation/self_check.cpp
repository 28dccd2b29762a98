// What the emulated runtime keeps of a GPU (cuda_runtime.h), each shown by a
// small scene whose answer is known: tests/engine/test_gpu_emulation.py runs
// them, so that the emulation is known to catch what it is there to catch.
#include <cmath>
#include <set>
#include <stdexcept>
#include <string>

#include "cuda/emulation_check.hpp"
#include "cuda/fixed_sums.cuh"

namespace engine {

namespace {

void ok(cudaError_t e, const char* what) {
  if (e != cudaSuccess) throw std::runtime_error(std::string(what) + ": " + cudaGetErrorString(e));
}

template <class F>
void launch_lanes(cudaStream_t s, unsigned int blocks, unsigned int lanes, F lane) {
  cuda_emu::launch(s, dim3(blocks), dim3(lanes), lane);
}

}  // namespace

std::map<std::string, double> cuda_emulation_check(const std::string& scene) {
  static const std::set<std::string> scenes{"stream_is_asynchronous", "legacy_copy_does_not_wait", "fresh_memory",
                                            "block_sum", "divergent_barrier", "graph_replays",
                                            "invalid_configuration", "host_touches_device_memory"};
  if (!scenes.count(scene)) throw std::invalid_argument("unknown emulation scene '" + scene + "'");
  std::map<std::string, double> r;
  cudaStream_t s;
  ok(cudaStreamCreateWithFlags(&s, cudaStreamNonBlocking), "stream");
  int* d = nullptr;
  int* h = nullptr;
  ok(cudaMalloc(&d, 4 * sizeof(int)), "cudaMalloc");
  ok(cudaMallocHost(&h, 4 * sizeof(int)), "cudaMallocHost");
  h[0] = h[1] = h[2] = h[3] = 0;
  if (scene == "stream_is_asynchronous") {
    // a result fetched by an async copy is the host's only after the wait
    ok(cudaMemset(d, 0, sizeof(int)), "memset");
    launch_lanes(s, 1, 1, [d] { d[0] = 42; });
    ok(cudaMemcpyAsync(h, d, sizeof(int), cudaMemcpyDeviceToHost, s), "copy");
    r["before_wait"] = h[0];
    ok(cudaStreamSynchronize(s), "wait");
    r["after_wait"] = h[0];
  } else if (scene == "legacy_copy_does_not_wait") {
    // cudaMemcpy (the legacy stream) does not wait for a non-blocking stream
    ok(cudaMemset(d, 0, sizeof(int)), "memset");
    launch_lanes(s, 1, 1, [d] { d[0] = 7; });
    ok(cudaMemcpy(h, d, sizeof(int), cudaMemcpyDeviceToHost), "copy");
    r["without_wait"] = h[0];
    ok(cudaStreamSynchronize(s), "wait");
    ok(cudaMemcpy(h, d, sizeof(int), cudaMemcpyDeviceToHost), "copy");
    r["after_wait"] = h[0];
  } else if (scene == "fresh_memory") {
    double* x = nullptr;
    double v = 0.0;
    ok(cudaMalloc(&x, sizeof(double)), "cudaMalloc");
    ok(cudaMemcpy(&v, x, sizeof(double), cudaMemcpyDeviceToHost), "copy");
    ok(cudaMemcpy(h, d, sizeof(int), cudaMemcpyDeviceToHost), "copy");
    r["double_is_nan"] = std::isnan(v) ? 1.0 : 0.0;
    r["int"] = h[0];
    ok(cudaFree(x), "cudaFree");
  } else if (scene == "block_sum") {
    // the backend's fixed tree over 256 lanes (barriers on fibers), and
    // __syncthreads_or: lane l adds l; only lane 200 votes
    double* x = nullptr;
    ok(cudaMalloc(&x, sizeof(double)), "cudaMalloc");
    launch_lanes(s, 1, 256, [x, d] {
      __shared__ double shared[256];
      const double total = block_sum<256>(double(threadIdx.x), shared);
      const int any = __syncthreads_or(threadIdx.x == 200);
      const int none = __syncthreads_or(0);
      if (threadIdx.x == 0) {
        x[0] = total;
        d[0] = any;
        d[1] = none;
      }
    });
    double total = 0.0;
    ok(cudaStreamSynchronize(s), "wait");
    ok(cudaMemcpy(&total, x, sizeof(double), cudaMemcpyDeviceToHost), "copy");
    ok(cudaMemcpy(h, d, 2 * sizeof(int), cudaMemcpyDeviceToHost), "copy");
    r["sum"] = total;
    r["or_one_votes"] = h[0];
    r["or_none_votes"] = h[1];
    ok(cudaFree(x), "cudaFree");
  } else if (scene == "divergent_barrier") {
    // lane 0 ends before a barrier the others wait at: a fault at the wait
    launch_lanes(s, 1, 32, [] {
      if (threadIdx.x == 0) return;
      __syncthreads();
    });
    const cudaError_t e = cudaStreamSynchronize(s);
    r["error"] = double(e);
    r["message_names_barrier"] = std::string(cudaGetErrorString(e)).find("__syncthreads") != std::string::npos;
    cudaGetLastError();
  } else if (scene == "graph_replays") {
    ok(cudaMemset(d, 0, sizeof(int)), "memset");
    ok(cudaStreamBeginCapture(s, cudaStreamCaptureModeThreadLocal), "capture");
    launch_lanes(s, 2, 8, [d] {
      if (blockIdx.x == 1 && threadIdx.x == 7) d[0] += 1;
    });
    cudaGraph_t g;
    cudaGraphExec_t x;
    ok(cudaStreamEndCapture(s, &g), "capture");
    ok(cudaStreamSynchronize(s), "wait");
    ok(cudaMemcpy(h, d, sizeof(int), cudaMemcpyDeviceToHost), "copy");
    r["after_capture"] = h[0];  // captured, not run
    ok(cudaGraphInstantiate(&x, g, 0), "instantiate");
    ok(cudaGraphLaunch(x, s), "launch");
    ok(cudaGraphLaunch(x, s), "launch");
    ok(cudaStreamSynchronize(s), "wait");
    ok(cudaMemcpy(h, d, sizeof(int), cudaMemcpyDeviceToHost), "copy");
    r["after_two_launches"] = h[0];
    cudaGraphExecDestroy(x);
    cudaGraphDestroy(g);
  } else if (scene == "invalid_configuration") {
    launch_lanes(s, 1, 2048, [] {});
    r["error"] = double(cudaGetLastError());
    r["cleared"] = double(cudaGetLastError());
  } else if (scene == "host_touches_device_memory") {
    // stops the process, saying so (run it in a process of its own)
    d[0] = 1;
  }
  cudaFreeHost(h);
  cudaFree(d);
  cudaStreamDestroy(s);
  return r;
}

}  // namespace engine
