// The touching pairs' islands by union-find over their nodes (friction_islands.hpp).
#include "contact/friction_islands.hpp"

#include <algorithm>
#include <numeric>

namespace engine {

void friction_islands(int32_t n_pairs, const int32_t* node, int32_t n_nodes, FrictionIslands& out,
                      std::vector<int32_t>& owner) {
  if (owner.size() < size_t(n_nodes)) owner.resize(size_t(n_nodes), -1);
  // parent[p]: a pair of p's island nearer its root; a root is its island's
  // lowest pair (unions keep the lower root), so numbering roots in pair
  // order numbers the islands by their first pair
  std::vector<int32_t>& parent = out.of_pair;
  parent.resize(size_t(n_pairs));
  std::iota(parent.begin(), parent.end(), 0);
  const auto root = [&parent](int32_t p) {
    while (parent[p] != p) p = parent[p] = parent[parent[p]];  // path halving
    return p;
  };
  constexpr int32_t kAhead = 8;  // pairs: the owner entries are cache misses (the step evicted them)
  for (int32_t p = 0; p < n_pairs; ++p) {
    if (p + kAhead < n_pairs)
      for (int k = 0; k < 6; ++k) __builtin_prefetch(&owner[node[6 * int64_t(p + kAhead) + k]], 1);
    for (int k = 0; k < 6; ++k) {
      int32_t& o = owner[node[6 * int64_t(p) + k]];
      if (o < 0) {
        o = p;
        continue;
      }
      const int32_t a = root(p), b = root(o);
      if (a < b) parent[b] = a;
      if (b < a) parent[a] = b;
    }
  }
  for (int64_t e = 0; e < 6 * int64_t(n_pairs); ++e) owner[node[e]] = -1;
  // every pair to its root, then the roots numbered in pair order (a root
  // comes before the rest of its island)
  for (int32_t p = 0; p < n_pairs; ++p) parent[p] = root(p);
  std::vector<int32_t> size, number(static_cast<size_t>(n_pairs));
  for (int32_t p = 0; p < n_pairs; ++p) {
    if (parent[p] == p) {
      number[p] = int32_t(size.size());
      size.push_back(0);
    }
    ++size[number[parent[p]]];
  }
  for (int32_t p = 0; p < n_pairs; ++p) parent[p] = number[parent[p]];
  const int32_t n_islands = int32_t(size.size());
  out.start.assign(size_t(n_islands) + 1, 0);
  for (int32_t i = 0; i < n_islands; ++i) out.start[i + 1] = out.start[i] + size[i];
  out.pair.resize(size_t(n_pairs));
  std::vector<int32_t> fill(out.start.begin(), out.start.end() - 1);
  for (int32_t p = 0; p < n_pairs; ++p) out.pair[fill[out.of_pair[p]]++] = p;
  out.by_size.resize(size_t(n_islands));
  std::iota(out.by_size.begin(), out.by_size.end(), 0);
  std::stable_sort(out.by_size.begin(), out.by_size.end(),
                   [&size](int32_t a, int32_t b) { return size[a] > size[b]; });
}

void one_island(int32_t n_pairs, FrictionIslands& out) {
  out.of_pair.assign(size_t(n_pairs), 0);
  out.start = {0, n_pairs};
  out.pair.resize(size_t(n_pairs));
  std::iota(out.pair.begin(), out.pair.end(), 0);
  out.by_size = {0};
}

}  // namespace engine
