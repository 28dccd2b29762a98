// The candidate list laid out for the GPU's contact stages (docs/gpu.md): the
// normal pass (cuda/contact_normal.cu) and friction (cuda/friction.cu) read
// one layout, made once per candidate list on the host.
//
// The candidates come in the CPU's pair order, (contactor, target)
// ascending, the order in which the CPU lists its touching pairs. Each node
// lists its entries 6 c + k (candidate c, corner k: the contactor's three
// nodes, then the target's) in candidate order. A node is at most one corner
// of a candidate (the broad phase never pairs triangles that share a node,
// broad_phase.hpp), so that is also the order in which the CPU adds a node's
// pair forces, the normal pass (a pair's six nodes in turn) and friction
// (corners 0, 3, 1, 4, 2, 5) alike: a lane per node adding its touching
// entries in this order gives the CPU's sums.
#pragma once
#include <cstdint>
#include <vector>

#include "contact/broad_phase.hpp"

namespace engine {

struct CandidateLayout {
  std::vector<int32_t> contactor, target;  // triangles, per candidate
  std::vector<int32_t> node;               // 6 per candidate
  std::vector<uint64_t> key;               // friction_pair_key, per candidate
  std::vector<int32_t> start;              // node i's entries: entry[start[i], start[i + 1])
  std::vector<int32_t> entry;              // 6 c + k
  int32_t size() const { return int32_t(contactor.size()); }
};

// `tri`: 3 node ids per triangle, every id < n_nodes. Throws
// std::invalid_argument when a candidate's two triangles share a node (the
// per-node order above would not hold) or the list has more than 2^31 / 6
// candidates.
void lay_out_candidates(const std::vector<CandidatePair>& candidates, const int32_t* tri, int32_t n_nodes,
                        CandidateLayout& out);

}  // namespace engine
