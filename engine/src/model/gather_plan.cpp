#include "model/gather_plan.hpp"

#include "model/threading.hpp"

namespace engine {

void GatherPlan::build(const Triangles& tris, const NodeGather& gather, int32_t n_nodes, int nt,
                       uint64_t topology_version) {
  const int32_t m = tris.size();
  threads = nt;
  topology = topology_version;
  thread_chunk.assign(size_t(nt) + 1, 0);
  chunk_begin.clear();
  chunk_end.clear();
  std::vector<int32_t> block_begin(nt), block_end(nt);
  for (int t = 0; t < nt; ++t) {
    block(m, t, nt, block_begin[t], block_end[t]);
    thread_chunk[t] = int32_t(chunk_begin.size());
    for (int32_t b = block_begin[t]; b < block_end[t]; b += kChunk) {
      chunk_begin.push_back(b);
      chunk_end.push_back(b + kChunk < block_end[t] ? b + kChunk : block_end[t]);
    }
  }
  thread_chunk[nt] = int32_t(chunk_begin.size());
  const int32_t n_chunks = int32_t(chunk_begin.size());
  // Each node's chunk: the one holding its last corner, if its first corner
  // is in the same thread's block; -1 (after the barrier) otherwise.
  std::vector<int32_t> chunk_of(n_nodes, -1);
  node_start.assign(size_t(n_chunks) + 1, 0);
  straddling.clear();
  int thread_of_first = 0;
  for (int32_t i = 0; i < n_nodes; ++i) {
    const int32_t s0 = gather.start[i], s1 = gather.start[i + 1];
    if (s0 == s1) continue;  // no corners: nothing to gather early (refused at build anyway)
    const int32_t first = gather.slot[s0] / 3, last = gather.slot[s1 - 1] / 3;  // slots ascend
    thread_of_first = 0;
    while (thread_of_first + 1 < nt && first >= block_end[thread_of_first]) ++thread_of_first;
    if (last >= block_end[thread_of_first]) {
      straddling.push_back(i);
      continue;
    }
    const int32_t c = thread_chunk[thread_of_first] + (last - block_begin[thread_of_first]) / kChunk;
    chunk_of[i] = c;
    ++node_start[c + 1];
  }
  for (int32_t c = 0; c < n_chunks; ++c) node_start[c + 1] += node_start[c];
  nodes.resize(node_start[n_chunks]);
  std::vector<int32_t> fill(node_start.begin(), node_start.end() - 1);
  for (int32_t i = 0; i < n_nodes; ++i)
    if (chunk_of[i] >= 0) nodes[fill[chunk_of[i]]++] = i;
}

}  // namespace engine
