// When each node's corner forces can be gathered in the element pass.
//
// The element pass writes every triangle's corner loads; the gather then
// sums them onto nodes in each node's fixed slot order. Done as two sweeps,
// the second reads ~13 MB of corner records back from L3 on the paper mesh
// (a fifth of a step). With the mesh numbered for locality
// (icerubble/geometry/mesh_order.py), most nodes' triangles lie within a
// few hundred triangles of each other in one thread's block: such a node is
// gathered right after the chunk of triangles holding its last corner is
// computed, while those records are still in L2. Nodes whose triangles span
// two threads' blocks are gathered after the barrier. Every node's sum is
// the same fixed-order sum as with a separate sweep.
#pragma once
#include <cstdint>
#include <vector>

#include "common/mesh_arrays.hpp"

namespace engine {

struct GatherPlan {
  static constexpr int32_t kChunk = 512;  // triangles per chunk: ~70 kB of corner records
  int threads = 0;
  uint64_t topology = ~uint64_t(0);  // Model's topology version the plan was made for
  std::vector<int32_t> thread_chunk;  // threads + 1: first chunk of each thread
  std::vector<int32_t> chunk_begin, chunk_end;  // per chunk: its triangles [begin, end)
  std::vector<int32_t> node_start;    // chunks + 1: CSR into nodes
  std::vector<int32_t> nodes;         // the nodes complete after each chunk, ascending
  std::vector<int32_t> straddling;    // nodes gathered after the barrier, ascending

  // The plan for triangles split into `threads` blocks as threading.hpp's block().
  void build(const Triangles& tris, const NodeGather& gather, int32_t n_nodes, int threads,
             uint64_t topology_version);
};

}  // namespace engine
