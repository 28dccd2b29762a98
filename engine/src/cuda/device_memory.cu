// The cache of GPU memory blocks (cuda/device_memory.hpp).
#include "cuda/device_memory.hpp"

#include <cuda_runtime.h>

#include <map>
#include <mutex>
#include <stdexcept>
#include <string>

namespace engine {

namespace {

struct Cache {
  std::mutex lock;
  std::multimap<size_t, void*> free_blocks;  // class -> block
  std::map<void*, size_t> in_use;            // block -> class
  bool given_since_wait = false;
  DeviceMemoryCounts counts;
};

// Never destroyed: blocks in use at exit belong to arrays destroyed after
// static destructors may have run, and the driver frees the context anyway.
Cache& cache() {
  static Cache* c = new Cache;
  return *c;
}

void fail(const char* what, cudaError_t e) {
  throw std::runtime_error(std::string("GPU: ") + what + ": " + cudaGetErrorString(e));
}

// Frees every cached block (the caller holds the lock).
void release_locked(Cache& c) {
  if (c.free_blocks.empty()) return;
  const cudaError_t e = cudaDeviceSynchronize();
  if (e != cudaSuccess) fail("device wait before freeing cached memory", e);
  for (const auto& b : c.free_blocks) cudaFree(b.second);
  c.free_blocks.clear();
  c.counts.cached_bytes = 0;
  c.given_since_wait = false;
}

}  // namespace

size_t device_size_class(size_t bytes) {
  constexpr size_t kSmall = 4096, kAlign = 256;
  if (bytes <= kSmall) return (bytes + kAlign - 1) / kAlign * kAlign;
  size_t top = kSmall;  // the largest power of two <= bytes
  while (top <= bytes / 2) top *= 2;
  const size_t step = top / 8;
  return (bytes + step - 1) / step * step;
}

void* device_take(size_t bytes) {
  Cache& c = cache();
  const size_t size = device_size_class(bytes);
  std::lock_guard<std::mutex> g(c.lock);
  auto it = c.free_blocks.find(size);
  if (it != c.free_blocks.end()) {
    void* p = it->second;
    c.free_blocks.erase(it);
    if (c.given_since_wait) {
      const cudaError_t e = cudaDeviceSynchronize();
      if (e != cudaSuccess) fail("device wait before reusing memory", e);
      c.given_since_wait = false;
      ++c.counts.waits;
    }
#ifdef ICERUBBLE_CUDA_EMULATION
    cudaMemset(p, 0xff, size);  // as fresh memory (the device is idle: waited above or never used)
#endif
    c.in_use[p] = size;
    c.counts.cached_bytes -= size;
    c.counts.used_bytes += size;
    ++c.counts.reuses;
    return p;
  }
  void* p = nullptr;
  cudaError_t e = cudaMalloc(&p, size);
  if (e == cudaErrorMemoryAllocation && !c.free_blocks.empty()) {  // the cache gives its memory back
    cudaGetLastError();
    release_locked(c);
    e = cudaMalloc(&p, size);
  }
  if (e != cudaSuccess) fail("cudaMalloc", e);
  c.in_use[p] = size;
  c.counts.used_bytes += size;
  ++c.counts.allocations;
  return p;
}

void device_give(void* p) {
  if (!p) return;
  Cache& c = cache();
  std::lock_guard<std::mutex> g(c.lock);
  auto it = c.in_use.find(p);
  if (it == c.in_use.end()) {  // not the cache's (never happens): freed as before
    cudaFree(p);
    return;
  }
  c.free_blocks.emplace(it->second, p);
  c.counts.cached_bytes += it->second;
  c.counts.used_bytes -= it->second;
  c.in_use.erase(it);
  c.given_since_wait = true;
}

DeviceMemoryCounts device_memory_counts() {
  Cache& c = cache();
  std::lock_guard<std::mutex> g(c.lock);
  return c.counts;
}

}  // namespace engine
