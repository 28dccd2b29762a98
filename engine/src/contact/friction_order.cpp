// Greedy colouring of the touching pairs in priority order (friction_order.hpp).
#include "contact/friction_order.hpp"

#include <omp.h>

#include <algorithm>

namespace engine {
namespace {

// A pair by priority, its nodes alongside: the greedy pass then reads the
// pairs in memory order, not through an index.
struct Ranked {
  uint64_t priority;
  int32_t pair;
  int32_t node[6];
};

// The pairs `of` (n of them) ranked by priority into `ranked`.
void rank(const int32_t* of, int32_t n, const int32_t* node, const uint64_t* key, std::vector<Ranked>& ranked) {
  ranked.resize(size_t(n));
  for (int32_t i = 0; i < n; ++i) {
    const int32_t p = of[i];
    ranked[i].priority = friction_priority(key[p]);
    ranked[i].pair = p;
    std::copy(node + 6 * int64_t(p), node + 6 * int64_t(p) + 6, ranked[i].node);
  }
  std::sort(ranked.begin(), ranked.end(), [](const Ranked& a, const Ranked& b) {
    return coloured_before(a.priority, a.pair, b.priority, b.pair);
  });
}

// Each ranked pair, in turn, takes the lowest colour none of its nodes has.
// used[words * n + w]: the colours taken at node n (bit c of word w is colour
// 64 w + c). False where a pair found all 64 words colours taken (the caller
// tries again with more words); `used` is left all zero at the pairs' nodes.
bool colour_greedy(const std::vector<Ranked>& ranked, int32_t words, uint64_t* used, int32_t* colour) {
  bool full = false;
  for (const Ranked& r : ranked) {
    const int32_t* v = r.node;
    int32_t c = -1;
    for (int32_t w = 0; w < words && c < 0; ++w) {
      uint64_t taken = 0;
      for (int k = 0; k < 6; ++k) taken |= used[size_t(words) * v[k] + w];
      if (~taken) c = 64 * w + __builtin_ctzll(~taken);
    }
    if (c < 0) {
      full = true;
      break;
    }
    colour[r.pair] = c;
    for (int k = 0; k < 6; ++k) used[size_t(words) * v[k] + c / 64] |= uint64_t(1) << (c % 64);
  }
  for (const Ranked& r : ranked)
    for (int k = 0; k < 6; ++k) std::fill_n(used + size_t(words) * r.node[k], words, uint64_t(0));
  return !full;
}

// A counting sort by colour, pair order within a colour.
void sort_by_colour(const std::vector<int32_t>& colour, FrictionOrder& out) {
  const int32_t n_pairs = int32_t(colour.size());
  const int32_t n_colours = 1 + *std::max_element(colour.begin(), colour.end());
  out.colour_start.assign(n_colours + 1, 0);
  for (int32_t p = 0; p < n_pairs; ++p) ++out.colour_start[colour[p] + 1];
  for (int32_t c = 0; c < n_colours; ++c) out.colour_start[c + 1] += out.colour_start[c];
  std::vector<int32_t> fill(out.colour_start.begin(), out.colour_start.end() - 1);
  for (int32_t p = 0; p < n_pairs; ++p) out.pair[fill[colour[p]]++] = p;
}

}  // namespace

void friction_order(int32_t n_pairs, const int32_t* node, const uint64_t* key, int32_t n_nodes,
                    const FrictionIslands& islands, int threads, FrictionOrder& out, std::vector<uint64_t>& used) {
  out.pair.resize(n_pairs);
  out.colour_start.assign(1, 0);
  if (n_pairs == 0) return;
  // A pair's colour depends on the pairs before it that share its nodes: its
  // island's alone, which other threads' islands never touch (not in `used`
  // either: the islands' nodes are apart). One word of `used` a node holds
  // 64 colours; a pile's pairs need ~10.
  std::vector<int32_t> colour(n_pairs);
  const int32_t n_islands = islands.count();
  for (int32_t words = 1;; words *= 2) {
    if (used.size() < size_t(words) * n_nodes) used.assign(size_t(words) * n_nodes, 0);
    bool all = true;
    #pragma omp parallel num_threads(threads) if (threads > 1) reduction(&& : all)
    {
      std::vector<Ranked> ranked;
      #pragma omp for schedule(dynamic, 1)
      for (int32_t r = 0; r < n_islands; ++r) {
        const int32_t i = islands.by_size[r];
        rank(islands.pair.data() + islands.start[i], islands.start[i + 1] - islands.start[i], node, key, ranked);
        all = colour_greedy(ranked, words, used.data(), colour.data()) && all;
      }
    }
    if (all) break;
  }
  sort_by_colour(colour, out);
}

}  // namespace engine
