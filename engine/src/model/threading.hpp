// How the model's passes share the nodes and triangles among threads: fixed
// contiguous blocks, so every sum is taken in the same order at a fixed
// thread count.
#pragma once
#include <cstdint>

namespace engine {

constexpr int kMaxThreads = 256;
// Below this many triangles a step is a few tens of microseconds of work and
// waking a second thread (twice per step) costs more than it saves.
constexpr int32_t kMinParallelTriangles = 2048;

// Thread t of nt takes [begin, end) of n items.
inline void block(int64_t n, int t, int nt, int32_t& begin, int32_t& end) {
  begin = int32_t(n * t / nt);
  end = int32_t(n * (t + 1) / nt);
}

}  // namespace engine
