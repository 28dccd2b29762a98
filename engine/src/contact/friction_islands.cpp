// The touching pairs' islands by union-find over their nodes (friction_islands.hpp).
#include "contact/friction_islands.hpp"

#include <algorithm>
#include <numeric>
#include <utility>

namespace engine {

namespace {

int32_t load(const int32_t& x) { return __atomic_load_n(&x, __ATOMIC_RELAXED); }

// x = desired where x still holds expected; else expected = x.
bool swap_if(int32_t& x, int32_t& expected, int32_t desired) {
  return __atomic_compare_exchange_n(&x, &expected, desired, false, __ATOMIC_RELAXED, __ATOMIC_RELAXED);
}

// parent[p] <= p (a root is its island's lowest pair), so the walk ends.
int32_t root_of(int32_t* parent, int32_t p) {
  for (int32_t q; (q = load(parent[p])) != p;) p = q;
  return p;
}

// The islands of a and b joined by threads at once: the higher root is hung
// under the lower where it is still a root, else tried again from the roots.
void join(int32_t* parent, int32_t a, int32_t b) {
  for (;;) {
    a = root_of(parent, a);
    b = root_of(parent, b);
    if (a == b) return;
    if (a < b) std::swap(a, b);
    int32_t expected = a;
    if (swap_if(parent[a], expected, b)) return;
  }
}

constexpr int32_t kAhead = 8;  // pairs: the owner entries are cache misses (the step evicted them)

void prefetch_owners(const int32_t* node, const std::vector<int32_t>& owner, int32_t p, int32_t n_pairs) {
  if (p + kAhead < n_pairs)
    for (int k = 0; k < 6; ++k) __builtin_prefetch(&owner[node[6 * int64_t(p + kAhead) + k]], 1);
}

}  // namespace

void friction_islands(int32_t n_pairs, const int32_t* node, int32_t n_nodes, FrictionIslands& out,
                      std::vector<int32_t>& owner, int threads) {
  if (owner.size() < size_t(n_nodes)) owner.resize(size_t(n_nodes), -1);
  // parent[p]: a pair of p's island nearer its root; a root is its island's
  // lowest pair (unions keep the lower root), so numbering roots in pair
  // order numbers the islands by their first pair. Which pair owns a node
  // (the first to claim it) and the order of the unions depend on the
  // threads; the islands do not.
  std::vector<int32_t>& parent = out.of_pair;
  parent.resize(size_t(n_pairs));
  int32_t* up = parent.data();
  #pragma omp parallel num_threads(threads) if (threads > 1)
  {
    #pragma omp for schedule(static)
    for (int32_t p = 0; p < n_pairs; ++p) parent[p] = p;
    #pragma omp for schedule(static)
    for (int32_t p = 0; p < n_pairs; ++p) {
      prefetch_owners(node, owner, p, n_pairs);
      for (int k = 0; k < 6; ++k) {
        int32_t& o = owner[node[6 * int64_t(p) + k]];
        int32_t other = load(o);
        if (other < 0 && swap_if(o, other, p)) continue;  // claimed; else other is the owner
        join(up, p, other);
      }
    }
    // every pair to its root (an ancestor: safe beside other walks)
    #pragma omp for schedule(static)
    for (int32_t p = 0; p < n_pairs; ++p) __atomic_store_n(&up[p], root_of(up, p), __ATOMIC_RELAXED);
    #pragma omp for schedule(static)
    for (int64_t e = 0; e < 6 * int64_t(n_pairs); ++e) __atomic_store_n(&owner[node[e]], -1, __ATOMIC_RELAXED);
  }
  // the roots numbered in pair order (a root comes before the rest of its island)
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
