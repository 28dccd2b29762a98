// Normal contact pass: broad phase, then the potential contact pair kernel on
// every candidate pair (in parallel, one result slot per candidate), each
// thread listing its chunk's touching candidates; the touching pairs are
// sorted into (contactor, target) order and made in parallel, then scattered
// onto the nodes serially in that order, so that the sums in fx, fy do not
// depend on the thread count at all. A loaded pile has ~1,000 touching pairs
// among ~40,000 candidates: the scatter is cheap; the walk over every
// candidate that listed them was serial (no change measured on two threads
// when it went: docs/gpu.md, "The CPU engine on a workstation").
#include <omp.h>

#include <chrono>
#include <cmath>
#include <stdexcept>

#include "contact/contact.hpp"
#include "common/input_errors.hpp"
#include "common/parameter_range.hpp"
#include "engine_parameter_ranges.hpp"

#include <algorithm>

namespace engine {
namespace {

// Below this many candidate pairs the kernel loop runs serially: waking the
// threads would cost more than it saves; likewise the touching pairs' making.
constexpr int64_t kMinParallelPairs = 2048;
constexpr int64_t kMinParallelTouching = 256;
// Candidates a thread takes at a time in the normal pass (a few microseconds
// of box tests where none touch).
constexpr int64_t kCandidateChunk = 512;

double now_s() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

}  // namespace

void validate(const ContactParams& p) {
  check(registry::penalty, p.penalty);
  check(registry::mu, p.mu);
}

ContactParams validated_contact_params(double penalty, double mu) {
  const ContactParams p{penalty, mu};
  validate(p);
  return p;
}

void ContactSolver::set_skin_fraction(double f) {
  if (!(std::isfinite(f) && f >= 0.0 && f <= 1.0))
    throw std::invalid_argument("skin_fraction must be in [0, 1]");
  skin_fraction_ = f;
  have_list_ = false;
}

namespace {

// FNV-style hash of what the candidate list depends on besides positions.
uint64_t list_signature(const ContactInput& in) {
  uint64_t h = 1469598103934665603ull;
  auto mix = [&h](uint64_t v) { h = (h ^ v) * 1099511628211ull; };
  mix(static_cast<uint64_t>(in.n_nodes));
  mix(static_cast<uint64_t>(in.n_surface));
  for (int32_t i = 0; i < in.n_surface; ++i) {
    const int64_t t = in.surface_tris[i];
    mix(static_cast<uint64_t>(t));
    mix(static_cast<uint64_t>(in.body[t]));
    for (int k = 0; k < 3; ++k) mix(static_cast<uint64_t>(in.tri[3 * t + k]));
  }
  return h;
}

}  // namespace

// True when the candidate list of the last build still holds every pair whose
// boxes can overlap now: no node of a surface triangle moved more than the skin.
// Both tests run every step over every surface triangle: the topology is
// compared by the host's version number where it keeps one (hashing ~40,000
// surface triangles every step cost 2-5 % of a paper-scene step, on one
// thread while the other waited), and the skin test is shared by the threads.
bool ContactSolver::list_still_valid(const ContactInput& in) const {
  if (!have_list_ || skin_fraction_ == 0.0) return false;
  if (static_cast<int64_t>(xref_.size()) != in.n_nodes) return false;
  if (in.topology_version != list_topology_) return false;
  if (in.topology_version == 0 && list_signature(in) != list_signature_) return false;
  const double skin = broad_.skin();
  const double* xr = xref_.data();
  const double* yr = yref_.data();
  const int32_t ns = in.n_surface;
  const int nthreads = ns < kMinParallelPairs ? 1 : (in.threads > 0 ? in.threads : omp_get_max_threads());
  int moved = 0;
#pragma omp parallel for schedule(static) num_threads(nthreads) if (nthreads > 1) reduction(| : moved)
  for (int32_t i = 0; i < ns; ++i) {
    const int32_t* v = in.tri + 3 * static_cast<int64_t>(in.surface_tris[i]);
    for (int k = 0; k < 3; ++k) {
      const int32_t n = v[k];
      // a NaN position forces a rebuild (which reports it)
      if (moved_past_skin(in.x[n], in.y[n], xr[n], yr[n], skin)) moved = 1;
    }
  }
  return !moved;
}

void ContactSolver::build_list(const ContactInput& in) {
  broad_.find(in.n_surface, in.surface_tris, in.tri, in.body, in.x, in.y, candidates_, in.threads, skin_fraction_);
  // In (contactor, target) order, the order of the touching pairs: each step
  // then lists them by walking the candidates, where sorting them took ~40 us
  // a step of a loaded paper pile on one thread (the list is built rarely).
  std::sort(candidates_.begin(), candidates_.end(), [](const CandidatePair& u, const CandidatePair& v) {
    return u.a != v.a ? u.a < v.a : u.b < v.b;
  });
  xref_.assign(in.x, in.x + in.n_nodes);
  yref_.assign(in.y, in.y + in.n_nodes);
  list_topology_ = in.topology_version;
  list_signature_ = in.topology_version == 0 ? list_signature(in) : 0;
  have_list_ = true;
  ++rebuilds_;
}

int32_t ContactSolver::compute_normal(const ContactParams& p, const ContactInput& in, double* fx,
                                      double* fy) {
  const double t0 = now_s();
  if (!list_still_valid(in)) build_list(in);
  const double t1 = now_s();

  const int64_t nc = static_cast<int64_t>(candidates_.size());
  if (static_cast<int64_t>(results_.size()) < nc) results_.resize(nc);
  const int nthreads = in.threads > 0 ? in.threads : omp_get_max_threads();
  const int team_wanted = nc >= kMinParallelPairs ? nthreads : 1;
  // Fixed chunks of the candidates, taken by the threads as they come free:
  // the touching ones, which cost the most, cluster (a paper pile's loaded
  // state: the busiest of 16 equal thread shares holds 1.34x the mean of
  // them). Each chunk lists its touching candidates; the lists, joined in
  // chunk order, are in candidate order whatever the thread count.
  const int64_t n_chunks = (nc + kCandidateChunk - 1) / kCandidateChunk;
  if (static_cast<int64_t>(chunk_hits_.size()) < n_chunks) chunk_hits_.resize(size_t(n_chunks));
#pragma omp parallel for schedule(dynamic, 1) num_threads(team_wanted) if (team_wanted > 1)
  for (int64_t c = 0; c < n_chunks; ++c) {
    std::vector<int64_t>& mine = chunk_hits_[size_t(c)];
    mine.clear();
    for (int64_t i = c * kCandidateChunk, end = std::min(nc, i + kCandidateChunk); i < end; ++i) {
      const int32_t* va = in.tri + 3 * static_cast<int64_t>(candidates_[i].a);
      const int32_t* vb = in.tri + 3 * static_cast<int64_t>(candidates_[i].b);
      const double xa[3] = {in.x[va[0]], in.x[va[1]], in.x[va[2]]};
      const double ya[3] = {in.y[va[0]], in.y[va[1]], in.y[va[2]]};
      const double xb[3] = {in.x[vb[0]], in.x[vb[1]], in.x[vb[2]]};
      const double yb[3] = {in.y[vb[0]], in.y[vb[1]], in.y[vb[2]]};
      // Candidates carry a skin: those whose current boxes are apart are no hit.
      if (contact_candidate(xa, ya, xb, yb, p.penalty, results_[i])) mine.push_back(i);
    }
  }

  // Touching pairs in (contactor, target) order (the candidates' order), not
  // in the order a broad phase happened to find them: forces are then summed,
  // and friction solved, in an order fixed by the state alone, so a run
  // resumed from a checkpoint (with a freshly built list) continues bit for bit.
  hits_.clear();
  for (int64_t c = 0; c < n_chunks; ++c)
    hits_.insert(hits_.end(), chunk_hits_[size_t(c)].begin(), chunk_hits_[size_t(c)].end());
  const int64_t nh = static_cast<int64_t>(hits_.size());
  pairs_.resize(static_cast<size_t>(nh));
  // the pairs' nodes and keys side by side: their islands' input and the
  // friction's colouring's
  pair_nodes_.resize(6 * static_cast<size_t>(nh));
  pair_keys_.resize(static_cast<size_t>(nh));
#pragma omp parallel for schedule(static) num_threads(nthreads) if (nh >= kMinParallelTouching)
  for (int64_t h = 0; h < nh; ++h) {
    const int64_t i = hits_[h];
    const PairContact& r = results_[i];
    ContactPair& cp = pairs_[h];
    cp.contactor = candidates_[i].a;
    cp.target = candidates_[i].b;
    for (int k = 0; k < 3; ++k) {
      cp.node[k] = in.tri[3 * static_cast<int64_t>(cp.contactor) + k];
      cp.node[3 + k] = in.tri[3 * static_cast<int64_t>(cp.target) + k];
      cp.nc[k] = r.nc[k];
      cp.nt[k] = r.nt[k];
    }
    std::copy(cp.node, cp.node + 6, pair_nodes_.begin() + 6 * h);
    pair_keys_[h] = friction_pair_key(cp.contactor, cp.target);
    contact_resultant(r, cp.fn, cp.nx, cp.ny);
    cp.px = r.px;
    cp.py = r.py;
    cp.energy = r.energy;
  }
  // A node's forces in pair order, the same at any thread count: where the
  // threads share the pairs, island by island (no two islands share a node).
  islands_of_pairs_ = share_by_islands(nthreads, nh);
  if (islands_of_pairs_)
    friction_islands(int32_t(nh), pair_nodes_.data(), in.n_nodes, islands_, island_owner_, nthreads);
  const auto add = [&](int32_t h) {
    const PairContact& r = results_[hits_[h]];
    const ContactPair& cp = pairs_[h];
    for (int k = 0; k < 6; ++k) {
      fx[cp.node[k]] += r.fx[k];
      fy[cp.node[k]] += r.fy[k];
    }
  };
  if (islands_of_pairs_) {
    const int32_t* island_pair = islands_.pair.data();
#pragma omp parallel for schedule(dynamic, 1) num_threads(nthreads)
    for (int32_t r = 0; r < islands_.count(); ++r) {
      const int32_t isl = islands_.by_size[r];
      for (int32_t s = islands_.start[isl]; s < islands_.start[isl + 1]; ++s) add(island_pair[s]);
    }
  } else {
    for (int32_t h = 0; h < int32_t(nh); ++h) add(h);
  }
  double energy = 0.0;
  for (int64_t h = 0; h < nh; ++h) energy += pairs_[h].energy;  // in pair order
  stored_energy_ = energy;
  n_touching_ = static_cast<int32_t>(pairs_.size());
  const double t2 = now_s();
  timings_.detection_s += t1 - t0;
  timings_.forces_s += t2 - t1;
  return n_touching_;
}

}  // namespace engine
