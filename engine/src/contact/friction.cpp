// Coulomb friction (paper eq 4, docs/model.md §3.2) with an exact stick state.
//
// Eq 4 as printed, f = -mu |f_c| v_t/|v_t|, is undefined at v_t = 0 and, in an
// explicit scheme, makes a block resting on a slope below the friction angle
// chatter and creep. Instead each touching pair carries a tangential force
// lambda, |lambda| <= mu |f_c|, chosen from the velocities the nodes will have
// at the end of this step, v' = v + dt f / m, where f already holds every other
// force of the step:
//   - if a force within the cone stops the tangential relative velocity at the
//     contact point, it is applied (stick: the block stays exactly at rest);
//   - otherwise lambda = -mu |f_c| sign(v_t') (slip: eq 4 with the end-of-step
//     sliding direction).
// Pairs that share nodes are coupled; projected Gauss-Seidel sweeps over the
// pairs, warm-started from the previous step's forces, resolve that. The
// sweeps visit the pairs colour by colour (no two pairs of a colour share a
// node; contact/friction_order.hpp), an order fixed by the state alone, so a
// colour's pairs can be updated at once on the GPU with the CPU's bits. The
// per-pair physics is contact/friction_kernel.hpp, shared with the GPU. The
// force acts at the contact point and is spread by the shape functions of both
// triangles, so it has zero resultant and zero moment over the pair.
#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>

#include "contact/contact.hpp"
#include "contact/friction_kernel.hpp"

namespace engine {
namespace {

// Sweeps are cheap (touching pairs only); 4 resolve the coupling between
// neighbouring pairs well enough, and the rest carries over to the next step.
constexpr int kSweeps = 4;

// The phases run threaded, colour by colour, where the colours hold this many
// pairs on average: each colour is a barrier in each of six phases, ~0.5-1 us
// each on two threads. Measured on two threads (bench/gpu_friction.py): 1,283
// pairs in 30 colours took 0.26 ms on one thread and 0.32 ms threaded, 13,581
// in 32 colours 3.9 and 2.7 ms. A loaded paper pile has ~1,000 pairs in ~15-30
// colours: its threads share the pairs' islands instead (friction_islands.hpp).
constexpr int64_t kMinPairsPerColour = 256;

// The nodes' friction values the sweeps read and write: the mesh's arrays
// (local null: node n at n) or an island's own (node n at local[n]).
struct FrictionNodes {
  double *wx, *wy, *imx, *imy;
  const int32_t* local;
};

}  // namespace

double ContactSolver::apply_friction(const ContactParams& p, const ContactInput& in, double* fx,
                                     double* fy) {
  if (p.mu == 0.0 || pairs_.empty()) {
    lambda_.assign(pairs_.size(), 0.0);
    order_.pair.clear();
    order_.colour_start.assign(1, 0);
    prev_key_.clear();
    prev_lambda_.clear();
    friction_power_ = 0.0;
    return 0.0;
  }
  if (!(std::isfinite(in.dt) && in.dt > 0.0))
    throw std::invalid_argument("contact friction needs a time step dt > 0");
  const auto t0 = std::chrono::steady_clock::now();
  const double dt = in.dt;
  const size_t np = pairs_.size();
  if (lambda_.size() < np) lambda_.resize(np);

  // the pairs' nodes, keys and (where the threads share them) islands come
  // from the normal pass (contact.cpp)
  const int nthreads = in.threads > 0 ? in.threads : omp_get_max_threads();
  const bool threaded = share_by_islands(nthreads, int64_t(np));
  if (threaded && !islands_of_pairs_)
    friction_islands(int32_t(np), pair_nodes_.data(), in.n_nodes, islands_, island_owner_, nthreads);
  if (!threaded) one_island(int32_t(np), islands_);
  islands_of_pairs_ = threaded;
  engine::friction_order(int32_t(np), pair_nodes_.data(), pair_keys_.data(), in.n_nodes, islands_,
                         threaded ? nthreads : 1, order_, order_used_);
  sweep_.resize(np);
  slip_work_.resize(np);
  const int32_t* colour_start = order_.colour_start.data();
  const int32_t colours = order_.colours();
  // The threads share the pairs island by island (no barrier: an island's
  // sweeps touch its nodes alone), or colour by colour where one island holds
  // more than a thread's share and the colours are large (a pressed wall).
  const bool by_colour = threaded && int64_t(np) >= kMinPairsPerColour * colours &&
                         int64_t(islands_.largest()) * nthreads > int64_t(np);

  // Per-component inverse masses (0 for an immovable or prescribed
  // component) and end-of-step velocities without friction of global node n,
  // in entry l of the arrays of V.
  const auto predict = [&](int32_t n, int32_t l, const FrictionNodes& V) {
    friction_predict_node(in.mass[n], in.constrained ? in.constrained[n] : 0, in.vx[n], in.vy[n], fx[n], fy[n],
                          in.v_bc_x, in.v_bc_y, n, dt, V.imx[l], V.imy[l], V.wx[l], V.wy[l]);
  };
  // Pair i copied into sweep_[s], its nodes as V numbers them: the pairs of
  // a colour are scattered over pairs_, and the sweeps visit each pair five
  // times (warm start, four sweeps); packed, each visit reads the pairs in
  // memory order.
  // Warm start from the force the same triangle pair carried last step: a
  // resting block needs nearly the same friction every step, so the sweeps
  // only correct it, and the iteration keeps converging across steps
  // instead of leaving a residual slip (creep) at a fixed sweep count.
  const auto warm_start = [&](int32_t s, int32_t i, const FrictionNodes& V) {
    const ContactPair& cp = pairs_[i];
    SweepPair& q = sweep_[s];
    for (int j = 0; j < 6; ++j) q.node[j] = V.local ? V.local[cp.node[j]] : cp.node[j];
    std::copy(cp.nc, cp.nc + 3, q.nc);
    std::copy(cp.nt, cp.nt + 3, q.nt);
    q.nx = cp.nx;
    q.ny = cp.ny;
    q.limit = p.mu * cp.fn;
    q.kinv = friction_inverse_mass(q.node, cp.nc, cp.nt, cp.nx, cp.ny, V.imx, V.imy);
    q.lambda = 0.0;
    q.fn_zero = cp.fn == 0.0;
    const int64_t at = find_key(prev_key_.data(), int64_t(prev_key_.size()), pair_keys_[i]);
    if (at < 0 || q.kinv == 0.0) return;
    q.lambda = clamp_to_cone(prev_lambda_[at], q.limit);
    friction_push(q.node, q.nc, q.nt, q.nx, q.ny, q.lambda, dt, V.imx, V.imy, V.wx, V.wy);
  };
  const auto update = [&](int32_t s, const FrictionNodes& V) {
    SweepPair& q = sweep_[s];
    if (q.kinv == 0.0 || q.fn_zero) return;
    const double d = friction_update(q.node, q.nc, q.nt, q.nx, q.ny, q.limit, q.kinv, dt, V.wx, V.wy, q.lambda);
    if (d != 0.0) friction_push(q.node, q.nc, q.nt, q.nx, q.ny, d, dt, V.imx, V.imy, V.wx, V.wy);
  };
  // Pair i (in sweep_[s]) as force onto its nodes, and its part of the power
  // of friction with the velocities the nodes will move with over this step
  // (what the energy balance integrates). A node's forces come in pair
  // order, as they do when the pairs are applied one after another.
  const auto apply = [&](int32_t i, int32_t s, const FrictionNodes& V) {
    const ContactPair& c = pairs_[i];
    const double lam = lambda_[i];
    slip_work_[i] = 0.0;
    if (lam == 0.0) return;
    const double tx = -c.ny * lam, ty = c.nx * lam;
    for (int j = 0; j < 3; ++j) {
      fx[c.node[j]] += c.nc[j] * tx;
      fy[c.node[j]] += c.nc[j] * ty;
      fx[c.node[3 + j]] -= c.nt[j] * tx;
      fy[c.node[3 + j]] -= c.nt[j] * ty;
    }
    slip_work_[i] = lam * friction_slip(sweep_[s].node, c.nc, c.nt, c.nx, c.ny, V.wx, V.wy);
  };

  if (by_colour) {
    // Each phase visits the pairs colour by colour (no two pairs of a colour
    // share a node), a barrier between colours, so its threads write disjoint
    // nodes and the bits are those of one thread visiting them in that order.
    // The nodes' arrays are the mesh's, each node at its own number.
    if (wx_.size() < static_cast<size_t>(in.n_nodes)) {
      wx_.resize(in.n_nodes);
      wy_.resize(in.n_nodes);
      imx_.resize(in.n_nodes);
      imy_.resize(in.n_nodes);
    }
    const FrictionNodes V{wx_.data(), wy_.data(), imx_.data(), imy_.data(), nullptr};
    const int32_t* order = order_.pair.data();
    slot_of_.resize(np);
    #pragma omp parallel num_threads(nthreads)
    {
      for (int32_t c = 0; c < colours; ++c) {
        #pragma omp for schedule(static)
        for (int32_t k = colour_start[c]; k < colour_start[c + 1]; ++k)
          for (int j = 0; j < 6; ++j) predict(pairs_[order[k]].node[j], pairs_[order[k]].node[j], V);
      }
      for (int32_t c = 0; c < colours; ++c) {
        #pragma omp for schedule(static)
        for (int32_t k = colour_start[c]; k < colour_start[c + 1]; ++k) warm_start(k, order[k], V);
      }
      for (int sweep = 0; sweep < kSweeps; ++sweep) {
        for (int32_t c = 0; c < colours; ++c) {
          #pragma omp for schedule(static)
          for (int32_t k = colour_start[c]; k < colour_start[c + 1]; ++k) update(k, V);
        }
      }
      #pragma omp for schedule(static)
      for (int64_t k = 0; k < int64_t(np); ++k) {
        lambda_[order[k]] = sweep_[k].lambda;
        slot_of_[order[k]] = int32_t(k);
      }
    }
    for (int32_t i = 0; i < int32_t(np); ++i) apply(i, slot_of_[i], V);
  } else {
    // Island by island, each island's pairs in sweep order: sweep_[s] holds
    // pair slot_[s], the islands one after another (slot_of_[i]: pair i's s).
    // An island's nodes are numbered in the order its pairs meet them and
    // kept in its thread's own short arrays: its sweeps read and write them
    // there, in cache, where the mesh's arrays put each node's four values
    // on four lines (shared with other threads' nodes).
    slot_.resize(np);
    slot_of_.resize(np);
    std::vector<int32_t> fill(islands_.start.begin(), islands_.start.end() - 1);
    for (int32_t k = 0; k < int32_t(np); ++k) {
      const int32_t i = order_.pair[k];
      slot_of_[i] = fill[islands_.of_pair[i]]++;
      slot_[slot_of_[i]] = i;
    }
    if (local_of_.size() < size_t(in.n_nodes)) local_of_.resize(size_t(in.n_nodes), -1);
    if (island_nodes_.size() < size_t(nthreads)) island_nodes_.resize(size_t(nthreads));
    const int32_t* slot = slot_.data();
    const int32_t* island_pair = islands_.pair.data();
    int32_t* local = local_of_.data();
    #pragma omp parallel for schedule(dynamic, 1) num_threads(nthreads) if (threaded)
    for (int32_t r = 0; r < islands_.count(); ++r) {
      const int32_t isl = islands_.by_size[r], b = islands_.start[isl], e = islands_.start[isl + 1];
      IslandNodes& W = island_nodes_[size_t(threaded ? omp_get_thread_num() : 0)];
      W.node.clear();
      for (int32_t s = b; s < e; ++s)
        for (int j = 0; j < 6; ++j) {
          const int32_t n = pairs_[slot[s]].node[j];
          if (local[n] >= 0) continue;
          local[n] = int32_t(W.node.size());
          W.node.push_back(n);
        }
      const size_t nl = W.node.size();
      if (W.wx.size() < nl) {
        W.wx.resize(nl);
        W.wy.resize(nl);
        W.imx.resize(nl);
        W.imy.resize(nl);
      }
      const FrictionNodes V{W.wx.data(), W.wy.data(), W.imx.data(), W.imy.data(), local};
      for (size_t l = 0; l < nl; ++l) predict(W.node[l], int32_t(l), V);
      for (int32_t s = b; s < e; ++s) warm_start(s, slot[s], V);
      for (int sweep = 0; sweep < kSweeps; ++sweep)
        for (int32_t s = b; s < e; ++s) update(s, V);
      for (int32_t s = b; s < e; ++s) lambda_[slot[s]] = sweep_[s].lambda;
      for (int32_t s = b; s < e; ++s) apply(island_pair[s], slot_of_[island_pair[s]], V);  // pair order
      for (const int32_t n : W.node) local[n] = -1;
    }
  }

  // Remember the forces by pair for the next step's warm start: the pairs
  // come in (contactor, target) order, i.e. with ascending keys.
  prev_key_.assign(pair_keys_.begin(), pair_keys_.end());
  prev_lambda_.assign(lambda_.begin(), lambda_.begin() + np);
  double dissipation = 0.0;
  for (size_t i = 0; i < np; ++i)  // in pair order: the same sum on any thread count
    if (lambda_[i] != 0.0) dissipation -= slip_work_[i];
  timings_.forces_s += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  friction_power_ = dissipation;
  return dissipation;
}

}  // namespace engine
