// The touching pairs' islands (contact/friction.cpp): the sets of pairs that
// friction couples, a pair together with every pair that shares one of its
// nodes, and so on. Friction's sweeps over an island read and write that
// island's nodes alone, so the CPU's threads sweep different islands at once
// and give the bits of the serial sweep, each island's pairs in their sweep
// order; the colouring (contact/friction_order.hpp) is a greedy pass whose
// choices look at a pair's island only, so islands are coloured at once too.
// The normal pass (contact.cpp) finds them and adds its pairs' forces onto the
// nodes island by island (a node's in pair order, as on one thread).
// A loaded paper pile's hundreds of touching pairs fall into ~70-150 islands,
// the largest of ~40-50 pairs (bench/touching_churn.py), where its ~15-30
// colours hold too few pairs each to share among threads with a barrier per
// colour.
#pragma once
#include <cstdint>
#include <vector>

namespace engine {

// Fewer touching pairs than this are summed and swept on one thread: finding
// the islands (~50 us for 1,100 pairs on one thread here, 45 on two: its
// node lookups miss the cache) and starting the threads costs more than it
// saves. Measured on two threads (friction; the paper scene, ridge 1, fast):
// 153 pairs of its rest state in 35 islands took 41 us on one thread, 45 by
// islands; 1,106 of a nudged pile in 212 islands 304 and 283 us.
constexpr int64_t kMinIslandPairs = 256;

// Whether `threads` threads share `pairs` touching pairs island by island
// (the normal pass's node sums and friction alike).
inline bool share_by_islands(int threads, int64_t pairs) { return threads > 1 && pairs >= kMinIslandPairs; }

struct FrictionIslands {
  std::vector<int32_t> of_pair;  // island of each pair (numbered by their first pair)
  std::vector<int32_t> start;    // island i holds pair[start[i], start[i + 1])
  std::vector<int32_t> pair;     // the pairs island by island, ascending within one
  std::vector<int32_t> by_size;  // the islands, largest first (ties: lower number first)
  int32_t count() const { return start.empty() ? 0 : int32_t(start.size()) - 1; }
  int32_t largest() const { return by_size.empty() ? 0 : start[by_size[0] + 1] - start[by_size[0]]; }
};

// n_pairs pairs, node[6 p + k] their nodes (< n_nodes), on `threads` threads
// (the same islands on any number: the pairs claim nodes and join islands by
// compare-and-swap). `owner` is a workspace (kept between
// calls, all -1 between calls).
void friction_islands(int32_t n_pairs, const int32_t* node, int32_t n_nodes, FrictionIslands& out,
                      std::vector<int32_t>& owner, int threads);

// All n_pairs pairs as one island (a serial sweep: finding the islands would
// cost more than the work they share out).
void one_island(int32_t n_pairs, FrictionIslands& out);

}  // namespace engine
