// A stable sort of records by a small integer key (a node id), then by a
// comparison inside each key's bucket: what the mesh-wide passes that group
// edges or corners by node need. A bond split re-runs those passes over the
// whole mesh (rebuild_topology, the reference contact stiffness), and
// std::sort of the paper mesh's 260,000 edges was a third of a split step;
// the buckets hold a node's few edges, so this is a counting pass and a few
// insertion sorts. Records equal under (key, less) keep their input order.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

namespace engine {

// Sorts v by key(r) in [0, n_keys), then by less within a key; stable.
template <class T, class Key, class Less>
void bucket_sort(std::vector<T>& v, int32_t n_keys, Key key, Less less) {
  std::vector<int64_t> start(size_t(n_keys) + 1, 0);
  for (const T& r : v) ++start[size_t(key(r)) + 1];
  for (int32_t k = 0; k < n_keys; ++k) start[size_t(k) + 1] += start[size_t(k)];
  std::vector<T> out(v.size());
  {
    std::vector<int64_t> fill(start.begin(), start.end() - 1);
    for (const T& r : v) out[size_t(fill[size_t(key(r))]++)] = r;
  }
  for (int32_t k = 0; k < n_keys; ++k)  // insertion sort: a bucket holds a node's few records
    for (int64_t i = start[size_t(k)] + 1; i < start[size_t(k) + 1]; ++i) {
      const T r = out[size_t(i)];
      int64_t j = i;
      for (; j > start[size_t(k)] && less(r, out[size_t(j - 1)]); --j) out[size_t(j)] = out[size_t(j - 1)];
      out[size_t(j)] = r;
    }
  v.swap(out);
}

}  // namespace engine
