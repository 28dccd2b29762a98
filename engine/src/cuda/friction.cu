// Friction on the GPU (cuda/friction.hpp), in the candidate list's index space
// as a whole GPU step will run it: the candidates in the CPU's pair order
// ((contactor, target)), a lane per candidate finding whether it touches and,
// if so, its contact point's shape functions and its normal force's resultant
// with the pair kernel of contact/potential_contact_kernel.hpp (the CPU's
// touching pairs are these, in this order). The touching candidates are
// listed (compact_kernel), and each one's earlier touching neighbours (a lane
// per pair and node), inverse mass and warm start found in many blocks
// (prepare_kernel). One block colours them as the CPU colours its pairs
// (contact/friction_order.cpp), in parallel rounds over colours kept in its
// shared memory: a pair takes its colour once every neighbour that comes
// before it has one (Jones-Plassmann), which gives the greedy colouring's
// colours exactly; it then places them colour by colour. One block then solves the
// sweeps: the pairs of a colour share no node, so its lanes update them at
// once and a barrier closes the colour; a pair's updates see exactly what they
// see in the CPU's serial sweep (contact/friction.cpp), so the tangential
// forces are the CPU's bits. Then a lane per node adds its pairs' friction in
// the CPU's order.
#include "cuda/friction.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "cuda/friction_impl.cuh"

#include "contact/candidate_layout.hpp"
#include "contact/friction_kernel.hpp"
#include "contact/potential_contact_kernel.hpp"
#include "cuda/device_array.cuh"
#include "cuda/dynamic_shared.cuh"
#include "cuda/fixed_sums.cuh"
#include "cuda/stream.cuh"
#include "cuda/halt.cuh"
#include "cuda/launch.cuh"
#include "model/model.hpp"

namespace engine {

namespace {

constexpr int kBlock = 128;
constexpr int kSolveThreads = kWideBlock;
constexpr int kSweeps = 4;           // contact/friction.cpp's
constexpr int32_t kEarlier = 16;     // a touching pair's earlier neighbours listed per node (more: walked each round)
// the colouring keeps its colours in shared memory up to this many touching
// pairs (32 KB), in global memory beyond: a round then reads each earlier
// neighbour's colour in tens of cycles, not a trip to L2
constexpr int32_t kSharedSlots = 8192;
// the sweeps keep the velocities and inverse masses of the touching pairs'
// nodes in shared memory where they are at most this many (128 KB of dynamic
// shared memory; fewer where the GPU's blocks have less) and the pairs all
// held (HeldPair, kHeld below): a pass then reads and writes them there,
// where each read went to the L2 cache after the colour before had written
// them
constexpr int32_t kSharedNodes = 4096;
constexpr size_t kSharedNodeBytes = 4 * sizeof(double);  // velocity x, y, inverse mass x, y
// pairs a sweep lane holds through every pass (HeldPair): up to kHeld times
// the block's lanes are held, the rest read from the arrays each pass (a
// loaded pile has up to a few thousand touching pairs)
constexpr int kHeld = 4;


// Whether candidate c touches, and its contact point and normal force's
// resultant: the CPU's ContactPair of that pair, bit for bit.
__global__ void pair_kernel(const int32_t* halt, const double* x, const double* y, const int32_t* node, int64_t n,
                            double penalty, uint8_t* hit, double* nc, double* nt, double* nx, double* ny, double* fn) {
  if (halted(halt)) return;
  const int64_t c = int64_t(blockIdx.x) * blockDim.x + threadIdx.x;
  if (c >= n) return;
  const int32_t* v = node + 6 * c;
  const double xa[3] = {x[v[0]], x[v[1]], x[v[2]]}, ya[3] = {y[v[0]], y[v[1]], y[v[2]]};
  const double xb[3] = {x[v[3]], x[v[4]], x[v[5]]}, yb[3] = {y[v[3]], y[v[4]], y[v[5]]};
  PairContact r;
  const bool h = contact_candidate(xa, ya, xb, yb, penalty, r);
  hit[c] = h ? 1 : 0;
  if (!h) return;
  for (int k = 0; k < 3; ++k) {
    nc[3 * c + k] = r.nc[k];
    nt[3 * c + k] = r.nt[k];
  }
  contact_resultant(r, fn[c], nx[c], ny[c]);
}

__global__ void predict_kernel(const int32_t* halt, FrictionPredictArrays p, int32_t n) {
  if (halted(halt)) return;
  const int32_t i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i < n) friction_predict(p, i);
}

// This lane's contiguous chunk [lo, hi) of n entries, chunks in lane order
// (a scan over the lanes then places what each chunk holds in order).
__device__ inline void lane_chunk(int32_t n, int32_t& lo, int32_t& hi) {
  const int32_t chunk = (n + kSolveThreads - 1) / kSolveThreads;
  lo = min(n, int32_t(threadIdx.x) * chunk);
  hi = min(n, lo + chunk);
}

// The touching candidates, compacted: tp[0, m) in ascending order (the CPU's
// pair order), m in counts[c_touching], and slot_of[c] = s where tp[s] = c, and
// lambda zeroed, for the touching candidates only: what the kernels after it
// read of the others is their hit flag alone. One block: a lane counts a
// contiguous chunk, a scan over the lanes places the chunks. The kernels after it visit the m touching pairs
// alone: a step of the paper mesh has ~80-3,000 touching pairs among ~15,000
// candidates, and a lane per candidate in one block made each colouring round
// and each colour's sweep walk them all (bench/results/gpu_step_profile.json).
// It also says whether these are the touching pairs of the colouring kept
// from a step before (coloured_tp, counts[c_coloured]; c_same): the colours
// are then that colouring's, which prepare_kernel and colour_kernel leave as
// they are (a pile's touching set seldom changes at the start of its load,
// every step or two once points have split, bench/touching_churn.py: a
// comparison here costs little where it does not pay).
__global__ void __launch_bounds__(kSolveThreads, 1)
    compact_kernel(const int32_t* halt, const uint8_t* __restrict__ hit, int32_t n,
                   const int32_t* __restrict__ coloured_tp, int32_t* __restrict__ tp, int32_t* __restrict__ slot_of,
                   double* __restrict__ lambda, int32_t* __restrict__ counts) {
  // (__restrict__: the flags are bytes, which may alias anything, so each
  // store of a touching candidate's entries made the next flag's load wait
  // for it: a lane's chunk was read one trip to memory after another)
  if (halted(halt)) return;
  __shared__ int32_t scan[kSolveThreads];
  const int32_t kept = counts[c_coloured];  // -1: no colouring kept
  int32_t lo, hi;
  lane_chunk(n, lo, hi);
  int32_t own = 0;
  for (int32_t c = lo; c < hi; ++c) own += hit[c] ? 1 : 0;
  const int32_t upto = block_inclusive_scan<kSolveThreads>(own, scan);
  int32_t at = upto - own;
  int differs = 0;
  for (int32_t c = lo; c < hi; ++c)
    if (hit[c]) {
      slot_of[c] = at;
      lambda[c] = 0.0;
      differs |= at >= kept || coloured_tp[at] != c;
      tp[at++] = c;
    }
  differs = __syncthreads_or(differs);
  if (threadIdx.x == kSolveThreads - 1) {
    counts[c_touching] = upto;
    counts[c_same] = !differs && upto == kept;
  }
}

// A touching candidate's neighbours are the touching candidates of the
// entries of its six nodes (entry 6 q + k: candidate q); those coloured
// before it (coloured_before: the priority order of the CPU's greedy
// colouring, pp its priority) decide its colour. visit(q) for each of them
// on its node v, in the node's entry order, until it returns false; false
// then. (__restrict__: what a visit stores aliases none of these, so one
// entry's loads need not wait for the last entry's store.)
// The entries are read kWalkBatch at a time, each batch's candidates' flags
// and keys loaded together before any is looked at: one entry after another,
// each entry's loads waited for the last one's (entry, then its flag and
// key), and a node has tens of entries (prepare_kernel's time was its
// longest walk's).
constexpr int kWalkBatch = 4;
template <class Visit>
__device__ inline bool visit_earlier_on_node(int32_t p, uint64_t pp, int32_t v, const uint8_t* __restrict__ hit,
                                             const uint64_t* __restrict__ key, const int32_t* __restrict__ start,
                                             const int32_t* __restrict__ entry, Visit visit) {
  const int32_t end = start[v + 1];
  for (int32_t j0 = start[v]; j0 < end; j0 += kWalkBatch) {
    int32_t q[kWalkBatch];
    bool touching[kWalkBatch];
    uint64_t kq[kWalkBatch];
    for (int u = 0; u < kWalkBatch; ++u) q[u] = j0 + u < end ? entry[j0 + u] / 6 : -1;
    for (int u = 0; u < kWalkBatch; ++u) {
      touching[u] = q[u] >= 0 && hit[q[u]];
      kq[u] = q[u] >= 0 ? key[q[u]] : 0;
    }
    for (int u = 0; u < kWalkBatch; ++u) {
      if (!touching[u] || q[u] == p || !coloured_before(friction_priority(kq[u]), q[u], pp, p)) continue;
      if (!visit(q[u])) return false;
    }
  }
  return true;
}

// What the colouring reads of the pairs' earlier neighbours: prepare_kernel's
// lists (by slot), and the layout to walk a node whose list overflowed.
struct EarlierNeighbours {
  const int32_t* node;
  const uint8_t* hit;
  const uint64_t* key;
  const int32_t *start, *entry, *slot_of, *earlier, *n_earlier;
};

// Slot s's (candidate p's, priority pp's) earlier neighbours from its node k
// and that node's list entry j on (a walked node: from its start), each
// one's slot given to see(e) until it returns false: false then, k and j
// left where it stopped; true once all have been seen.
template <class See>
__device__ inline bool see_earlier(const EarlierNeighbours& E, int32_t s, int32_t p, uint64_t pp, int32_t& k,
                                   int32_t& j, See see) {
  for (; k < 6; ++k, j = 0) {
    // n_earlier -1: more than the list holds; the node is walked (each time)
    const int32_t count = E.n_earlier[6 * s + k];
    if (count >= 0) {
      const int32_t* list = E.earlier + int64_t(kEarlier) * (6 * s + k);
      for (; j < count; ++j)
        if (!see(list[j])) return false;
    } else if (!visit_earlier_on_node(p, pp, E.node[6 * p + k], E.hit, E.key, E.start, E.entry,
                                      [&](int32_t q) { return see(E.slot_of[q]); })) {
      return false;
    }
  }
  return true;
}

// Per touching pair (slot s < m, candidate p = tp[s]) and node k of its six,
// what does not change while it is coloured and solved: the slots of its
// earlier neighbours on that node (up to kEarlier, at 6 s + k; a pair sharing
// two nodes listed on both; n_earlier[6 s + k] = -1 where there are more),
// and, from lanes k = 0 and 1, its inverse effective mass and its warm start
// (NaN: none; both by candidate), which the CPU looks up as it pushes it. A lane per (pair,
// node), many blocks: each node's walk is a chain of dependent loads, so the
// six run side by side, as the pairs do, not one after another in a lane.
__global__ void prepare_kernel(const int32_t* halt, FrictionPairArrays P, const int32_t* tp, const int32_t* slot_of,
                               const int32_t* counts, const int32_t* start, const int32_t* entry,
                               const uint64_t* prev_key, const double* prev_lambda, int64_t n_prev,
                               bool by_candidate, double mu,
                               const double* imx, const double* imy, int32_t listed, int32_t* earlier,
                               int32_t* n_earlier, double* kinv, double* warm) {
  if (halted(halt)) return;
  const int64_t t = int64_t(blockIdx.x) * blockDim.x + threadIdx.x;
  const int32_t s = int32_t(t / 6), k = int32_t(t % 6);
  if (s >= counts[c_touching]) return;
  const int32_t p = tp[s];
  // the colouring kept (compact_kernel): its lists are not read again
  const bool listing = !counts[c_same];
  if (!listing && k > 1) return;
  int32_t* list = earlier + int64_t(kEarlier) * t;
  int32_t count = 0;
  const bool all = !listing || visit_earlier_on_node(p, friction_priority(P.key[p]), P.node[6 * p + k], P.hit, P.key, start, entry,
                                         [&](int32_t q) {
                                           // more than the list holds: the colouring walks the node itself
                                           if (count == listed) return false;
                                           list[count++] = slot_of[q];
                                           return true;
                                         });
  if (listing) n_earlier[t] = all ? count : -1;
  if (k > 1) return;
  const double km = friction_inverse_mass(P.node + 6 * p, P.nc + 3 * p, P.nt + 3 * p, P.nx[p], P.ny[p], imx, imy);
  if (k == 0) {
    kinv[p] = km;
    return;
  }
  // by_candidate: the warm start is laid out as the candidates (the whole
  // step's), so its entry is the candidate's own, where a binary search over
  // ~15,000 keys was a chain of ~14 loads in this lane
  const int64_t at = by_candidate ? int64_t(p) : find_key(prev_key, n_prev, P.key[p]);
  // NaN: a candidate that did not touch in the step before (the whole step
  // keeps the warm start per candidate, cuda/device_step.cu)
  warm[p] = (at < 0 || km == 0.0 || isnan(prev_lambda[at])) ? NAN : clamp_to_cone(prev_lambda[at], mu * P.fn[p]);
}

// The touching pairs' nodes numbered in the order of their first (slot,
// node), so the same for the same pairs (not in the order lanes reach them),
// into L, and their count in counts[c_nodes] (the node sums visit them,
// apply_touched_kernel); again in counts[c_local] where the sweeps keep them
// in shared memory, -1 there where they are more than L.most or the pairs
// more than the sweeps hold (kHeld per lane; the sweeps then read the nodes' arrays).
// `scan`: the block's buffer of kSolveThreads.
__device__ inline void number_local_nodes(const int32_t* node, const int32_t* tp, int32_t m, const LocalNodes& L,
                                          int32_t* counts, int32_t* scan) {
  const int32_t n6 = 6 * m;
  for (int32_t t = threadIdx.x; t < n6; t += kSolveThreads) atomicMin(&L.first_of[node[6 * tp[t / 6] + t % 6]], t);
  __syncthreads();
  int32_t lo, hi;
  lane_chunk(n6, lo, hi);
  int32_t own = 0;
  for (int32_t t = lo; t < hi; ++t) own += L.first_of[node[6 * tp[t / 6] + t % 6]] == t ? 1 : 0;
  const int32_t upto = block_inclusive_scan<kSolveThreads>(own, scan);
  if (threadIdx.x == kSolveThreads - 1) scan[0] = upto;  // the total, for every lane
  __syncthreads();
  const int32_t n_local = scan[0];
  const bool fits = m <= kHeld * kSolveThreads && n_local <= L.most;  // every pair held
  int32_t at = upto - own;
  for (int32_t t = lo; t < hi; ++t) {
    const int32_t v = node[6 * tp[t / 6] + t % 6];
    if (L.first_of[v] != t) continue;
    L.node[at] = v;
    L.node6[t] = at++;
  }
  __syncthreads();
  // a (slot, node) takes its node's number from that node's first; the first's own entry is read as it is
  for (int32_t t = threadIdx.x; t < n6; t += kSolveThreads) {
    const int32_t f = L.first_of[node[6 * tp[t / 6] + t % 6]];
    if (f != t) L.node6[t] = L.node6[f];
  }
  __syncthreads();
  for (int32_t t = threadIdx.x; t < n6; t += kSolveThreads) L.first_of[node[6 * tp[t / 6] + t % 6]] = INT32_MAX;
  if (threadIdx.x == 0) {
    counts[c_nodes] = n_local;
    counts[c_local] = fits ? n_local : -1;
  }
  __syncthreads();  // `scan` is the caller's again
}

// A slot's colour is -1 until it is coloured; a colour, once written, is
// final, so a lane that reads a neighbour's colour in the round it is written
// sees either -1 (and waits a round) or the final value. A pair takes the
// smallest colour none of its earlier neighbours has once they all have one.
// The colours are kept by slot in shared memory (up to kSharedSlots pairs;
// slot_colour beyond), then written by candidate (colour_out) and by slot.
// Where the touching pairs are those of the colouring kept (counts[c_same]),
// its outputs stand and nothing is done; otherwise the new colouring's pairs
// are kept with it (coloured_tp, counts[c_coloured]).
__global__ void __launch_bounds__(kSolveThreads, 1)
    colour_kernel(const int32_t* halt, EarlierNeighbours E, const int32_t* tp, int32_t* colour_out, int32_t* counts,
                  int32_t* slot_colour, int32_t* order, int32_t* colour_start, int32_t* coloured_tp,
                  LocalNodes L) {
  if (halted(halt) || counts[c_same]) return;
  __shared__ int32_t most[kSolveThreads];
  __shared__ int32_t shared_colour[kSharedSlots];
  const int32_t m = counts[c_touching];
  volatile int32_t* colour = m <= kSharedSlots ? shared_colour : slot_colour;
  for (int32_t s = threadIdx.x; s < m; s += kSolveThreads) colour[s] = -1;
  // The lane's first kHeld slots (s = its index + r times the block's lanes,
  // as the sweeps hold their pairs) each keep their way through their
  // earlier neighbours from round to round: the colours below 64 seen so far
  // (a colour, once written, is final) and the node and list entry waited
  // on, so a round reads the one colour each waits for, where it read the
  // lists again from their start. The first slot's in registers, the
  // others' in the lane's local memory.
  struct Resumed {
    int32_t p = 0, k = 0, j = 0;
    uint64_t pp = 0, seen = 0;
  };
  Resumed first_slot, more_slots[kHeld - 1];
  for (int r = 0; r < kHeld; ++r) {
    const int32_t s = int32_t(threadIdx.x) + r * kSolveThreads;
    if (s >= m) break;
    Resumed& w = r == 0 ? first_slot : more_slots[r - 1];
    w.p = tp[s];
    w.pp = friction_priority(E.key[w.p]);
  }
  // slot s's next round on its way (w): 1 coloured, 0 waiting, -1 colours 0-63 all taken
  const auto resume = [&](int32_t s, Resumed& w) {
    // a colour, once written, is final: the bits seen stay right
    const bool ready = see_earlier(E, s, w.p, w.pp, w.k, w.j, [&](int32_t e) {
      const int32_t c = colour[e];
      if (c >= 0 && c < 64) w.seen |= uint64_t(1) << c;
      return c >= 0;
    });
    if (!ready) return 0;
    if (~w.seen) {
      colour[s] = __ffsll((long long)~w.seen) - 1;
      return 1;
    }
    return -1;
  };
  __syncthreads();
  int32_t rounds = 0;
  for (;;) {
    ++rounds;
    int waiting = 0;
    for (int32_t s = threadIdx.x; s < m; s += kSolveThreads) {
      if (colour[s] != -1) continue;
      const int32_t r = (s - int32_t(threadIdx.x)) / kSolveThreads;
      if (r < kHeld) {
        const int done = resume(s, r == 0 ? first_slot : more_slots[r - 1]);
        if (done == 0) waiting = 1;
        if (done >= 0) continue;
        // colours 0-63 all taken: the scan below finds its colour from 64 up
      }
      const int32_t p = tp[s];
      const uint64_t pp = friction_priority(E.key[p]);
      bool ready = true;
      for (int32_t base = 0; ready; base += 64) {
        uint64_t taken = 0;
        int32_t k = 0, j = 0;
        // an earlier neighbour's colour (slot e): false (stop) while it has none
        ready = see_earlier(E, s, p, pp, k, j, [&](int32_t e) {
          const int32_t c = colour[e];
          if (c >= base && c < base + 64) taken |= uint64_t(1) << (c - base);
          return c >= 0;
        });
        if (ready && ~taken) {
          colour[s] = base + __ffsll((long long)~taken) - 1;
          break;
        }
      }
      if (!ready) waiting = 1;
    }
    if (!__syncthreads_or(waiting)) break;
    // every round colours the earliest pair not yet coloured, so a round past
    // the m-th is a bug: the launch fails (an error at the host's next wait)
    // rather than looping for ever
    if (rounds > m) __trap();
  }
  int32_t most_own = -1;
  for (int32_t s = threadIdx.x; s < m; s += kSolveThreads) {
    const int32_t c = colour[s];
    slot_colour[s] = c;
    colour_out[tp[s]] = c;
    coloured_tp[s] = tp[s];
    most_own = max(most_own, c);
  }
  most[threadIdx.x] = most_own;
  __syncthreads();
  for (int w = kSolveThreads / 2; w > 0; w /= 2) {
    if (int(threadIdx.x) < w) most[threadIdx.x] = max(most[threadIdx.x], most[threadIdx.x + w]);
    __syncthreads();
  }
  const int32_t colours = most[0] + 1;
  if (threadIdx.x == 0) {
    counts[c_colours] = colours;
    counts[c_rounds] = rounds;
    counts[c_coloured] = m;
    ++counts[c_colourings];
  }
  __syncthreads();  // `most` is the counters' buffer from here
  number_local_nodes(E.node, tp, m, L, counts, most);
  // The slots colour by colour: the sweeps then visit a colour's pairs alone.
  // Within a colour no two pairs share a node, so the sweeps' bits do not
  // depend on the order they take within it: each slot takes its place with
  // an atomic add on its colour's counter, a colour's places after a scan of
  // the counts, where a scan per colour made ~24 barriers a colour.
  if (colours <= kSolveThreads) {
    if (int32_t(threadIdx.x) < colours) most[threadIdx.x] = 0;
    __syncthreads();
    for (int32_t s = threadIdx.x; s < m; s += kSolveThreads) atomicAdd(&most[slot_colour[s]], 1);
    __syncthreads();
    const int32_t own = int32_t(threadIdx.x) < colours ? most[threadIdx.x] : 0;  // each lane its own entry
    const int32_t upto = block_inclusive_scan<kSolveThreads>(own, most);
    if (int32_t(threadIdx.x) < colours) {
      colour_start[threadIdx.x] = upto - own;
      most[threadIdx.x] = upto - own;  // the colour's next place
    }
    if (int32_t(threadIdx.x) == colours - 1) colour_start[colours] = upto;
    if (colours == 0 && threadIdx.x == 0) colour_start[0] = 0;
    __syncthreads();
    for (int32_t s = threadIdx.x; s < m; s += kSolveThreads) order[atomicAdd(&most[slot_colour[s]], 1)] = tp[s];
    return;
  }
  // more colours than lanes: a scan per colour over the lanes' chunks
  int32_t lo, hi;
  lane_chunk(m, lo, hi);
  int32_t base = 0;
  for (int32_t c = 0; c < colours; ++c) {
    int32_t own = 0;
    for (int32_t s = lo; s < hi; ++s) own += slot_colour[s] == c ? 1 : 0;
    const int32_t upto = block_inclusive_scan<kSolveThreads>(own, most);
    int32_t at = base + upto - own;
    for (int32_t s = lo; s < hi; ++s)
      if (slot_colour[s] == c) order[at++] = tp[s];
    if (threadIdx.x == 0) colour_start[c] = base;
    // the colour's total: the last lane's, read through the buffer after the scan
    if (threadIdx.x == kSolveThreads - 1) most[0] = upto;
    __syncthreads();
    base += most[0];
    __syncthreads();  // every lane has read the total before the next colour's scan
  }
  if (threadIdx.x == 0) colour_start[colours] = base;
}

// A touching pair's values that the sweeps read and do not change (its
// nodes, where it touches, its normal and normal force, its inverse mass),
// held by the lane that solves it through every pass, and its tangential
// force as it goes: a pass then loads its nodes' velocities alone, where it
// loaded the slot, the candidate and then these, one after another.
struct HeldPair {
  int32_t i;  // the candidate
  int32_t node[6];
  double nc[3], nt[3], nx, ny, fn, kinv, warm, lambda;
};

__device__ inline void hold_pair(const FrictionPairArrays& P, int32_t i, const double* kinv, double warm,
                                 const int32_t* node6, HeldPair& h) {
  h.i = i;
  // node6: the pair's nodes' local numbers (solve_kernel's shared arrays), else the mesh's
  for (int k = 0; k < 6; ++k) h.node[k] = node6 ? node6[k] : P.node[6 * i + k];
  for (int k = 0; k < 3; ++k) {
    h.nc[k] = P.nc[3 * i + k];
    h.nt[k] = P.nt[3 * i + k];
  }
  h.nx = P.nx[i];
  h.ny = P.ny[i];
  h.fn = P.fn[i];
  h.kinv = kinv[i];
  h.warm = warm;
  h.lambda = 0.0;  // as compact_kernel left lambda[i]
}

// A held pair's warm start push, and its update in a sweep (as the arrays' pairs').
__device__ inline void held_warm_push(HeldPair& hp, double dt, const double* ix, const double* iy, double* vx,
                                      double* vy) {
  if (isnan(hp.warm)) return;
  hp.lambda = hp.warm;
  friction_push(hp.node, hp.nc, hp.nt, hp.nx, hp.ny, hp.warm, dt, ix, iy, vx, vy);
}
__device__ inline void held_update(HeldPair& hp, double mu, double dt, const double* ix, const double* iy,
                                   double* vx, double* vy) {
  if (hp.kinv == 0.0 || hp.fn == 0.0) return;
  const double d = friction_update(hp.node, hp.nc, hp.nt, hp.nx, hp.ny, mu * hp.fn, hp.kinv, dt, vx, vy, hp.lambda);
  if (d != 0.0) friction_push(hp.node, hp.nc, hp.nt, hp.nx, hp.ny, d, dt, ix, iy, vx, vy);
}

// The sweeps, colour by colour with a barrier closing each colour. The
// pairs in colour order (order[j], j < m: their candidates) are shared among the lanes by j
// modulo the block's size, so a lane solves pairs j = its index + r times
// the block's size in every pass of their colours and holds them (HeldPair)
// for r < kHeld (m up to 4,096: a pile's load phase has ~80-3,000 touching
// pairs; the lease of 2026-11-30 timed the sweeps at 60 us with ~1,000 held
// and 207 with ~1,200, where pairs past the first 1,024 were read from
// memory each pass); its further pairs are read from memory each pass.
// (One block a multiprocessor, said: ptxas otherwise gave the lanes 32
// registers, for two blocks that never run, and spilled the held pairs.)
__global__ void __launch_bounds__(kSolveThreads, 1)
    solve_kernel(const int32_t* halt, FrictionPairArrays P, const int32_t* tp, const int32_t* order,
                 const int32_t* colour_start, const int32_t* counts, const double* warm, double mu, double dt,
                 const double* imx, const double* imy, double* wx, double* wy, const double* kinv, double* lambda,
                 double* power, LocalNodes L, const int32_t* slot_of) {
  if (halted(halt)) return;
  __shared__ double shared[kSolveThreads];
  __shared__ int32_t starts[kSolveThreads + 1];
  // L.most nodes' four values in the launch's dynamic shared memory
  double* const local_wx = dynamic_shared<double>();
  double* const local_wy = local_wx + L.most;
  double* const local_imx = local_wy + L.most;
  double* const local_imy = local_imx + L.most;
  const int32_t colours = counts[c_colours], m = counts[c_touching];
  // the touching pairs' nodes in shared memory (number_local_nodes: every pair held)
  const int32_t n_local = counts[c_local];
  const bool local = n_local >= 0;
  if (local) {
    for (int32_t a = threadIdx.x; a < n_local; a += kSolveThreads) {
      const int32_t v = L.node[a];
      local_wx[a] = wx[v];
      local_wy[a] = wy[v];
      local_imx[a] = imx[v];
      local_imy[a] = imy[v];
    }
  }
  // what the held pairs' passes read and write: the same values, by local number or by node
  double* const vx = local ? local_wx : wx;
  double* const vy = local ? local_wy : wy;
  const double* const ix = local ? local_imx : imx;
  const double* const iy = local ? local_imy : imy;
  const int32_t* cs = colour_start;
  if (colours <= kSolveThreads) {  // the colours' bounds, read every pass: from shared memory
    for (int32_t c = threadIdx.x; c <= colours; c += kSolveThreads) starts[c] = colour_start[c];
    __syncthreads();
    cs = starts;
  }
  const int32_t own = threadIdx.x;
  // the lane's pairs j = own + r kSolveThreads, r < kHeld: the first held in
  // registers, the others in the lane's local memory (an address of its own,
  // where a pair read from the arrays is a chain: order, then the pair, then
  // its nodes)
  HeldPair h{}, more[kHeld - 1];  // h set where own < m, read only there
  const auto hold = [&](int32_t j, HeldPair& hp) {
    const int32_t i = order[j];
    hold_pair(P, i, kinv, warm[i], local ? L.node6 + 6 * slot_of[i] : nullptr, hp);
  };
  if (own < m) hold(own, h);
  for (int r = 1; r < kHeld; ++r)
    if (own + r * kSolveThreads < m) hold(own + r * kSolveThreads, more[r - 1]);
  __syncthreads();  // the shared nodes loaded
  // this lane's first pair at or after a (j = its index modulo the block's size)
  const auto first = [&](int32_t a) {
    return a + int32_t((threadIdx.x + kSolveThreads - uint32_t(a) % kSolveThreads) % kSolveThreads);
  };
  // the warm start, colour by colour as the CPU pushes it
  for (int32_t c = 0; c < colours; ++c) {
    for (int32_t j = first(cs[c]); j < cs[c + 1]; j += kSolveThreads) {
      const int32_t r = (j - own) / kSolveThreads;  // j = own + r kSolveThreads
      if (r == 0) {
        held_warm_push(h, dt, ix, iy, vx, vy);
        continue;
      }
      if (r < kHeld) {
        held_warm_push(more[r - 1], dt, ix, iy, vx, vy);
        continue;
      }
      const int32_t i = order[j];
      if (isnan(warm[i])) continue;
      lambda[i] = warm[i];
      friction_push(P.node + 6 * i, P.nc + 3 * i, P.nt + 3 * i, P.nx[i], P.ny[i], warm[i], dt, imx, imy, wx, wy);
    }
    __syncthreads();
  }
  for (int sweep = 0; sweep < kSweeps; ++sweep) {
    for (int32_t c = 0; c < colours; ++c) {
      for (int32_t j = first(cs[c]); j < cs[c + 1]; j += kSolveThreads) {
        const int32_t r = (j - own) / kSolveThreads;
        if (r == 0) {
          held_update(h, mu, dt, ix, iy, vx, vy);
          continue;
        }
        if (r < kHeld) {
          held_update(more[r - 1], mu, dt, ix, iy, vx, vy);
          continue;
        }
        const int32_t i = order[j];
        if (kinv[i] == 0.0 || P.fn[i] == 0.0) continue;
        const int32_t* node = P.node + 6 * i;
        const double* nc = P.nc + 3 * i;
        const double* nt = P.nt + 3 * i;
        const double d = friction_update(node, nc, nt, P.nx[i], P.ny[i], mu * P.fn[i], kinv[i], dt, wx, wy, lambda[i]);
        if (d != 0.0) friction_push(node, nc, nt, P.nx[i], P.ny[i], d, dt, imx, imy, wx, wy);
      }
      __syncthreads();
    }
  }
  if (own < m) lambda[h.i] = h.lambda;
  for (int r = 1; r < kHeld; ++r)
    if (own + r * kSolveThreads < m) lambda[more[r - 1].i] = more[r - 1].lambda;
  if (local) {  // the velocities back to the nodes (the power reads them there)
    for (int32_t a = threadIdx.x; a < n_local; a += kSolveThreads) {
      wx[L.node[a]] = local_wx[a];
      wy[L.node[a]] = local_wy[a];
    }
  }
  __syncthreads();  // every held force is in lambda before the power reads it by slot
  // the power with the velocities the nodes will move with, summed in a fixed tree
  double p = 0.0;
  for (int32_t s = threadIdx.x; s < m; s += kSolveThreads) {
    const int32_t i = tp[s];
    if (lambda[i] != 0.0)
      p -= lambda[i] * friction_slip(P.node + 6 * i, P.nc + 3 * i, P.nt + 3 * i, P.nx[i], P.ny[i], wx, wy);
  }
  p = block_sum<kSolveThreads>(p, shared);
  if (threadIdx.x == 0) *power = p;
}

// Node i's force with its pairs' friction added in the CPU's order: pairs
// ascending, a pair's corners as the CPU visits them (contactor's j, then
// target's j, j = 0, 1, 2); entry 6 c + k names candidate c's node slot k.
// Four entries at a time, what each adds read before any is added (in entry
// order: the same sums), where each entry's loads waited for the last one's.
constexpr int kApplyBatch = 4;
__device__ inline void add_node_friction(const FrictionPairArrays& P, const int32_t* start, const int32_t* entry,
                                         const double* lambda, int32_t i, double& sx, double& sy) {
  const int32_t end = start[i + 1];
  for (int32_t j0 = start[i]; j0 < end; j0 += kApplyBatch) {
    int32_t p[kApplyBatch], k[kApplyBatch];
    double lam[kApplyBatch], tx[kApplyBatch] = {}, ty[kApplyBatch] = {}, w[kApplyBatch] = {};  // set where lam != 0, read only there
    for (int u = 0; u < kApplyBatch; ++u) {
      const int32_t e = j0 + u < end ? entry[j0 + u] : -1;
      p[u] = e >= 0 ? e / 6 : -1;
      k[u] = e % 6;
    }
    for (int u = 0; u < kApplyBatch; ++u) {
      // a candidate that does not touch has none (its lambda is not set): 0 here, never added
      lam[u] = p[u] >= 0 && P.hit[p[u]] ? lambda[p[u]] : 0.0;
      if (lam[u] == 0.0) continue;
      tx[u] = -P.ny[p[u]] * lam[u];
      ty[u] = P.nx[p[u]] * lam[u];
      w[u] = k[u] < 3 ? P.nc[3 * p[u] + k[u]] : P.nt[3 * p[u] + k[u] - 3];
    }
    for (int u = 0; u < kApplyBatch; ++u) {
      if (lam[u] == 0.0) continue;
      if (k[u] < 3) {
        sx += w[u] * tx[u];
        sy += w[u] * ty[u];
      } else {
        sx -= w[u] * tx[u];
        sy -= w[u] * ty[u];
      }
    }
  }
}

// Node i's total: its force before friction with its pairs' friction added.
__device__ inline void apply_node(const FrictionPairArrays& P, const int32_t* start, const int32_t* entry,
                                  const double* lambda, const double* f_pre_x, const double* f_pre_y, int32_t i,
                                  double* f_x, double* f_y) {
  double sx = f_pre_x[i], sy = f_pre_y[i];
  add_node_friction(P, start, entry, lambda, i, sx, sy);
  f_x[i] = sx;
  f_y[i] = sy;
}

__global__ void apply_kernel(const int32_t* halt, FrictionPairArrays P, const int32_t* start, const int32_t* entry,
                             const double* lambda, const double* f_pre_x, const double* f_pre_y, int32_t n, double* f_x,
                             double* f_y) {
  if (halted(halt)) return;
  const int32_t i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i < n) apply_node(P, start, entry, lambda, f_pre_x, f_pre_y, i, f_x, f_y);
}

// apply_kernel for the touching pairs' nodes alone (number_local_nodes),
// where f_x, f_y hold the total before friction already (the whole step:
// every other node's sum is that total, as apply_kernel leaves it): the same
// sums, a few hundred nodes in the load phase where apply_kernel visited all
// ~50,000 of the paper mesh and their candidates. A fixed grid of lanes steps
// through them.
__global__ void apply_touched_kernel(const int32_t* halt, FrictionPairArrays P, const int32_t* start,
                                     const int32_t* entry, const double* lambda, const double* f_pre_x,
                                     const double* f_pre_y, const int32_t* touched, const int32_t* counts,
                                     double* f_x, double* f_y) {
  if (halted(halt)) return;
  const int32_t n = counts[c_nodes];
  for (int32_t a = blockIdx.x * blockDim.x + threadIdx.x; a < n; a += gridDim.x * blockDim.x)
    apply_node(P, start, entry, lambda, f_pre_x, f_pre_y, touched[a], f_x, f_y);
}

int blocks(int64_t n) { return int((n + kBlock - 1) / kBlock); }

// The most nodes the sweeps keep in shared memory on this GPU: kSharedNodes,
// or what its blocks' shared memory holds beside solve_kernel's own arrays;
// the kernel is let use that much (over 48 KB it must opt in).
int32_t most_shared_nodes() {
  static const int32_t most = [] {
    int optin = 0;
    cuda_check(cudaDeviceGetAttribute(&optin, cudaDevAttrMaxSharedMemoryPerBlockOptin, 0), "cudaDeviceGetAttribute");
    const size_t own = sizeof(double) * kSolveThreads + sizeof(int32_t) * (kSolveThreads + 1);  // solve_kernel's
    const size_t room = size_t(optin) > own ? size_t(optin) - own : 0;
    const int32_t n = int32_t(std::min<size_t>(size_t(kSharedNodes), room / kSharedNodeBytes));
    cuda_check(cudaFuncSetAttribute(solve_kernel, cudaFuncAttributeMaxDynamicSharedMemorySize,
                                    int(kSharedNodeBytes * size_t(n))),
               "cudaFuncSetAttribute");
    return n;
  }();
  return most;
}
// apply_touched_kernel's grid (its lanes step through the touching pairs' nodes)
constexpr int kTouchedBlocks = 32;


}  // namespace

void DeviceFriction::Impl::launch() {
  if (n_cand && !pairs_given) {
    launch_kernel(pair_kernel, blocks(n_cand), kBlock, stream, halt, x.data(), y.data(), node.data(), n_cand, penalty,
                  hit.data(), nc.data(), nt.data(), nx.data(), ny.data(), fn.data());
  }
  if (!predicted)
    launch_kernel(predict_kernel, blocks(n_nodes), kBlock, stream, halt, predict_arrays(), n_nodes);
  launch_kernel(compact_kernel, 1, kSolveThreads, stream, halt, hit.data(), n_cand, coloured_tp.data(), tp.data(),
                slot_of.data(), lambda.data(), counts.data());
  if (n_cand)
    launch_kernel(prepare_kernel, blocks(6 * int64_t(n_cand)), kBlock, stream, halt, pairs(), tp.data(),
                  slot_of.data(), counts.data(), start.data(), entry.data(), prev_key.data(), prev_lambda.data(),
                  n_prev, warm_by_candidate, mu, imx.data(), imy.data(), earlier_list, earlier.data(),
                  n_earlier.data(), kinv.data(), warm.data());
  const EarlierNeighbours E{node.data(),    hit.data(),     key.data(),     start.data(),
                            entry.data(),   slot_of.data(), earlier.data(), n_earlier.data()};
  launch_kernel(colour_kernel, 1, kSolveThreads, stream, halt, E, tp.data(), colour.data(), counts.data(),
                slot_colour.data(), order.data(), colour_start.data(), coloured_tp.data(), local_nodes());
  launch_kernel_shared(solve_kernel, 1, kSolveThreads, kSharedNodeBytes * size_t(shared_nodes), stream, halt,
                       pairs(), tp.data(), order.data(), colour_start.data(),
                counts.data(), warm.data(), mu, dt, imx.data(), imy.data(), wx.data(), wy.data(), kinv.data(),
                lambda.data(), power.data(), local_nodes(), slot_of.data());
  if (totals_given)
    launch_kernel(apply_touched_kernel, kTouchedBlocks, kBlock, stream, halt, pairs(), start.data(), entry.data(),
                  lambda.data(), f_pre_x.data(), f_pre_y.data(), local_node.data(), counts.data(), f_x.data(),
                  f_y.data());
  else
    launch_kernel(apply_kernel, blocks(n_nodes), kBlock, stream, halt, pairs(), start.data(), entry.data(),
                  lambda.data(), f_pre_x.data(), f_pre_y.data(), n_nodes, f_x.data(), f_y.data());
  cuda_check(cudaGetLastError(), "kernel launch");
}


void DeviceFriction::Impl::size_pairs(size_t n) {
  n_cand = int32_t(n);
  hit.resize(n);
  for (auto* a : {&nx, &ny, &fn, &kinv, &lambda}) a->resize(n);
  nc.resize(3 * n);
  nt.resize(3 * n);
  colour.resize(n);
  tp.resize(n);
  slot_of.resize(n);
  slot_colour.resize(n);
  coloured_tp.resize(n);
  order.resize(n);
  colour_start.resize(n + 1);  // at most as many colours as touching pairs
  n_earlier.resize(6 * n);
  local_node6.resize(6 * n);
  local_node.resize(std::max(6 * n, size_t(kSharedNodes)));
  warm.resize(n);
  earlier.resize(size_t(6 * kEarlier) * n);
}

DeviceFriction::DeviceFriction(const Model& m, WarmStart warm_start) : impl_(new Impl) {
  Impl& d = *impl_;
  d.stream = new_stream();
  const Nodes& N = m.nodes();
  const ContactSolver& C = m.contact();
  const std::vector<CandidatePair>& cand = C.candidates();
  d.n_nodes = N.size();
  d.mu = m.contact_params().mu;
  d.penalty = m.contact_params().penalty;
  d.dt = m.dt();
  CandidateLayout L;  // the CPU's pair order, each node's entries in it
  lay_out_candidates(cand, m.triangles().node.data(), d.n_nodes, L);
  d.x.upload(N.x);
  d.y.upload(N.y);
  d.mass.upload(N.mass);
  d.constrained.upload(N.constrained);
  d.vx.upload(N.vx);
  d.vy.upload(N.vy);
  d.f_pre_x.upload(N.f_pre_x);
  d.f_pre_y.upload(N.f_pre_y);
  for (auto* a : {&d.imx, &d.imy, &d.wx, &d.wy, &d.f_x, &d.f_y}) a->resize(d.n_nodes);
  d.first_of.upload(std::vector<int32_t>(size_t(d.n_nodes), INT32_MAX));  // number_local_nodes' between colourings
  d.shared_nodes = most_shared_nodes();
  std::vector<int32_t> counts(n_friction_counts, 0);
  counts[c_coloured] = -1;  // no colouring kept
  d.counts.upload(counts);
  d.earlier_list = kEarlier;
  const std::vector<uint64_t>& wk = C.warm_start_keys();
  const std::vector<double>& wl = C.warm_start_forces();
  d.node.upload(L.node);
  d.key.upload(L.key);
  d.start.upload(L.start);
  d.entry.upload(L.entry);
  d.size_pairs(cand.size());
  d.warm_by_candidate = warm_start == WarmStart::per_candidate;
  if (warm_start == WarmStart::model_keys) {
    d.prev_key.upload(wk);
    d.prev_lambda.upload(wl);
    d.n_prev = int64_t(wk.size());
  } else {  // both key lists ascending: one merge
    std::vector<double> prev(L.key.size(), NAN);
    for (size_t c = 0, j = 0; c < L.key.size(); ++c) {
      while (j < wk.size() && wk[j] < L.key[c]) ++j;
      if (j < wk.size() && wk[j] == L.key[c]) prev[c] = wl[j];
    }
    d.prev_key.upload(L.key);
    d.prev_lambda.upload(prev);
    d.n_prev = int64_t(L.key.size());
  }
  d.power.resize(1);
}

void DeviceFriction::Impl::forget_colouring() {
  // -1 in every byte: the int32 -1
  cuda_check(cudaMemsetAsync(counts.data() + c_coloured, 0xff, sizeof(int32_t), stream), "memset");
}

DeviceFriction::~DeviceFriction() {
  if (impl_->stream) cudaStreamDestroy(impl_->stream);
}

void DeviceFriction::run() { impl_->launch(); }

int32_t DeviceFriction::candidates() const { return impl_->n_cand; }

void DeviceFriction::set_earlier_list(int32_t n) {
  if (n < 0 || n > kEarlier)
    throw std::invalid_argument("earlier_list=" + std::to_string(n) + ": valid values are 0 to " +
                                std::to_string(kEarlier));
  impl_->earlier_list = n;
}

void DeviceFriction::set_shared_nodes(int32_t n) {
  const int32_t most = most_shared_nodes();
  if (n < 0 || n > most)
    throw std::invalid_argument("shared_nodes=" + std::to_string(n) + ": valid values are 0 to " +
                                std::to_string(most));
  impl_->shared_nodes = n;
  impl_->forget_colouring();  // the nodes are numbered with the colouring
}

double DeviceFriction::time_per_run(int repeats) {
  Impl& d = *impl_;
  return mean_launch_seconds(d.stream, repeats, [&] { d.launch(); });
}

FrictionFields DeviceFriction::fields() {
  Impl& d = *impl_;
  cuda_check(cudaStreamSynchronize(d.stream), "GPU friction");
  FrictionFields f;
  f.f_x = d.f_x.download();
  f.f_y = d.f_y.download();
  // the touching candidates, in order: the CPU's pairs
  const std::vector<uint8_t> hit = d.hit.download();
  const std::vector<double> lambda = d.lambda.download();
  const std::vector<int32_t> colour = d.colour.download();
  for (size_t c = 0; c < hit.size(); ++c) {
    if (!hit[c]) continue;
    f.lambda.push_back(lambda[c]);
    f.colour.push_back(colour[c]);
  }
  f.power = d.power.download()[0];
  const std::vector<int32_t> counts = d.counts.download();
  f.colours = counts[c_colours];
  f.rounds = counts[c_rounds];
  f.colourings = counts[c_colourings];
  f.local_nodes = counts[c_local];
  return f;
}

}  // namespace engine
