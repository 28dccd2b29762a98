// Greedy colouring of the touching pairs in priority order (friction_order.hpp).
#include "contact/friction_order.hpp"

#include <algorithm>

namespace engine {

void friction_order(int32_t n_pairs, const int32_t* node, const uint64_t* key, int32_t n_nodes,
                    FrictionOrder& out, std::vector<uint64_t>& used) {
  out.pair.resize(n_pairs);
  out.colour_start.assign(1, 0);
  if (n_pairs == 0) return;
  // the pairs by priority, each with its nodes alongside: the greedy pass
  // then reads them in memory order, not through an index
  struct Ranked {
    uint64_t priority;
    int32_t pair;
    int32_t node[6];
  };
  std::vector<Ranked> ranked(n_pairs);
  for (int32_t p = 0; p < n_pairs; ++p) {
    ranked[p].priority = friction_priority(key[p]);
    ranked[p].pair = p;
    std::copy(node + 6 * int64_t(p), node + 6 * int64_t(p) + 6, ranked[p].node);
  }
  std::sort(ranked.begin(), ranked.end(), [](const Ranked& a, const Ranked& b) {
    return coloured_before(a.priority, a.pair, b.priority, b.pair);
  });
  // used[words * n + w]: the colours taken at node n (bit c of word w is
  // colour 64 w + c). One word holds 64 colours; a pile's pairs need ~10.
  std::vector<int32_t> colour(n_pairs);
  int32_t words = 1;
  for (;;) {
    if (used.size() < size_t(words) * n_nodes) used.assign(size_t(words) * n_nodes, 0);
    bool full = false;
    for (const Ranked& r : ranked) {
      const int32_t p = r.pair;
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
      colour[p] = c;
      for (int k = 0; k < 6; ++k) used[size_t(words) * v[k] + c / 64] |= uint64_t(1) << (c % 64);
    }
    // leave the workspace all zero for the next call
    for (int64_t e = 0; e < 6 * int64_t(n_pairs); ++e)
      std::fill_n(used.begin() + size_t(words) * node[e], words, uint64_t(0));
    if (!full) break;
    words *= 2;
    used.assign(size_t(words) * n_nodes, 0);
  }
  // a counting sort by colour, pair order within a colour
  const int32_t n_colours = 1 + *std::max_element(colour.begin(), colour.end());
  out.colour_start.assign(n_colours + 1, 0);
  for (int32_t p = 0; p < n_pairs; ++p) ++out.colour_start[colour[p] + 1];
  for (int32_t c = 0; c < n_colours; ++c) out.colour_start[c + 1] += out.colour_start[c];
  std::vector<int32_t> fill(out.colour_start.begin(), out.colour_start.end() - 1);
  for (int32_t p = 0; p < n_pairs; ++p) out.pair[fill[colour[p]]++] = p;
}

}  // namespace engine
