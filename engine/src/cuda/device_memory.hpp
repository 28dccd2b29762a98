// GPU memory for the backend's arrays (cuda/device_array.cuh), kept for
// reuse: an array given back goes into a cache by size class instead of to
// cudaFree, and a later array of that class takes it. The whole step makes
// its stages again after every host step (a bond split: ~800 in a 300 mm
// paper-depth run), about 150 arrays each time; cudaFree waits for the
// device and cudaMalloc maps memory, each time. A plain C++ header: the
// counts are read by the bindings of every build.
#pragma once
#include <cstddef>
#include <cstdint>

namespace engine {

struct DeviceMemoryCounts {
  int64_t allocations = 0;  // blocks cudaMalloc'd (fresh memory)
  int64_t reuses = 0;       // blocks handed out again from the cache
  int64_t waits = 0;        // device waits before a reuse (a block given back since the last one)
  size_t cached_bytes = 0;  // held in the cache now, not in use
  size_t used_bytes = 0;    // handed out now
};

// The process's counts so far (all zero in a build without the backend).
DeviceMemoryCounts device_memory_counts();

// The size a request of `bytes` is given: blocks of one class are
// interchangeable, and a class is at most 1/8 larger than the request, so an
// array that grows by a few split nodes keeps its class.
size_t device_size_class(size_t bytes);

// A block of at least `bytes` (its class), fresh or from the cache; a reuse
// first waits for the device when a block was given back since the last
// wait, as cudaFree would have waited before the memory could be used again
// (work queued before the give may still read it). Fresh memory is not zero;
// on the emulation a reused block is filled as fresh memory is (0xff), so a
// read of memory never written is caught there too.
void* device_take(size_t bytes);
// `p` (from device_take) back into the cache; no wait. The cache gives its
// blocks back to the device only where a cudaMalloc fails (then tries again).
void device_give(void* p);

}  // namespace engine
