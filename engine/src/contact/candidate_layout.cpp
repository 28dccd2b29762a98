#include "contact/candidate_layout.hpp"

#include <algorithm>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <string>

#include "contact/friction_kernel.hpp"  // friction_pair_key

namespace engine {

void lay_out_candidates(const std::vector<CandidatePair>& cand, const int32_t* tri, int32_t n_nodes,
                        CandidateLayout& out) {
  const size_t n = cand.size();
  if (n > size_t(std::numeric_limits<int32_t>::max() / 6))
    throw std::invalid_argument("contact candidates: " + std::to_string(n) + " candidates, more than the " +
                                std::to_string(std::numeric_limits<int32_t>::max() / 6) + " the GPU layout holds");
  std::vector<int32_t> order(n);
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](int32_t u, int32_t v) {
    return cand[u].a != cand[v].a ? cand[u].a < cand[v].a : cand[u].b < cand[v].b;
  });
  out.contactor.resize(n);
  out.target.resize(n);
  out.node.resize(6 * n);
  out.key.resize(n);
  for (size_t c = 0; c < n; ++c) {
    const CandidatePair& p = cand[order[c]];
    out.contactor[c] = p.a;
    out.target[c] = p.b;
    for (int k = 0; k < 3; ++k) {
      out.node[6 * c + k] = tri[3 * size_t(p.a) + k];
      out.node[6 * c + 3 + k] = tri[3 * size_t(p.b) + k];
    }
    for (int k = 0; k < 3; ++k)
      for (int j = 3; j < 6; ++j)
        if (out.node[6 * c + k] == out.node[6 * c + j])
          throw std::invalid_argument("contact candidates: triangles " + std::to_string(p.a) + " and " +
                                      std::to_string(p.b) + " share node " + std::to_string(out.node[6 * c + k]));
    out.key[c] = friction_pair_key(p.a, p.b);
  }
  // a counting sort of the entries by node, candidates ascending
  out.start.assign(size_t(n_nodes) + 1, 0);
  for (const int32_t v : out.node) ++out.start[size_t(v) + 1];
  for (int32_t i = 0; i < n_nodes; ++i) out.start[size_t(i) + 1] += out.start[size_t(i)];
  std::vector<int32_t> fill(out.start.begin(), out.start.end() - 1);
  out.entry.resize(out.node.size());
  for (size_t e = 0; e < out.node.size(); ++e) out.entry[size_t(fill[size_t(out.node[e])]++)] = int32_t(e);
}

}  // namespace engine
