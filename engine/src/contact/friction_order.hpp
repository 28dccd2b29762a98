// The order in which friction's Gauss-Seidel sweeps visit the touching pairs
// (contact/friction.cpp), the same on both backends: colour by colour, where
// no two pairs of a colour share a node, so the pairs of a colour can be
// updated at once (a GPU's lanes, a CPU's threads) and give the bits of any
// serial order. The colours are a greedy colouring in an order fixed by the
// pairs' keys alone ((contactor, target), hashed), so they depend on the
// state only: a resumed run, whose candidate list is built afresh, gets the
// same colours and continues bit for bit. Hashing the keys instead of taking
// them in pair order keeps the colouring's dependency chains short (the pair
// order made 32 rounds for 54 pairs on the paper mesh), so a GPU can compute
// the same colouring in a few parallel rounds (Jones-Plassmann).
#pragma once
#include <cstdint>
#include <vector>

#include "contact/friction_islands.hpp"
#include "contact/friction_kernel.hpp"  // friction_priority, coloured_before

namespace engine {

struct FrictionOrder {
  std::vector<int32_t> pair;          // the pairs, colour by colour, ascending within a colour
  std::vector<int32_t> colour_start;  // colour c is pair[colour_start[c], colour_start[c + 1])
  int32_t colours() const { return colour_start.empty() ? 0 : int32_t(colour_start.size()) - 1; }
};

// n_pairs pairs, node[6 p + k] their nodes (< n_nodes), key[p] their keys
// (friction_pair_key), coloured island by island (contact/friction_islands.hpp;
// one island of every pair gives the same colours) on `threads` threads.
// `used` is a workspace (kept between calls, all zero between calls).
void friction_order(int32_t n_pairs, const int32_t* node, const uint64_t* key, int32_t n_nodes,
                    const FrictionIslands& islands, int threads, FrictionOrder& out, std::vector<uint64_t>& used);

}  // namespace engine
