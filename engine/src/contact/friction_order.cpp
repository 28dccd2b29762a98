// Greedy colouring of the touching pairs in priority order (friction_order.hpp).
#include "contact/friction_order.hpp"

#include <algorithm>
#include <numeric>

namespace engine {

void friction_order(int32_t n_pairs, const int32_t* node, const uint64_t* key, int32_t n_nodes,
                    FrictionOrder& out, std::vector<uint64_t>& used) {
  out.pair.resize(n_pairs);
  out.colour_start.assign(1, 0);
  if (n_pairs == 0) return;
  std::vector<int32_t> by_priority(n_pairs);
  std::iota(by_priority.begin(), by_priority.end(), 0);
  std::vector<uint64_t> priority(n_pairs);
  for (int32_t p = 0; p < n_pairs; ++p) priority[p] = friction_priority(key[p]);
  std::sort(by_priority.begin(), by_priority.end(),
            [&](int32_t a, int32_t b) { return coloured_before(priority[a], a, priority[b], b); });
  // used[words * n + w]: the colours taken at node n (bit c of word w is
  // colour 64 w + c). One word holds 64 colours; a pile's pairs need ~10.
  std::vector<int32_t> colour(n_pairs);
  int32_t words = 1;
  for (;;) {
    if (used.size() < size_t(words) * n_nodes) used.assign(size_t(words) * n_nodes, 0);
    bool full = false;
    for (const int32_t p : by_priority) {
      const int32_t* v = node + 6 * int64_t(p);
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
