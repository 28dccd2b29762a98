// Friction on the GPU (cuda/friction.hpp), in the candidate list's index space
// as a whole GPU step will run it: the candidates in the CPU's pair order
// ((contactor, target)), a lane per candidate finding whether it touches and,
// if so, its contact point's shape functions and its normal force's resultant
// with the pair kernel of contact/potential_contact_kernel.hpp (the CPU's
// touching pairs are these, in this order). One block colours the touching
// candidates as the CPU colours its pairs (contact/friction_order.cpp), in
// parallel rounds: a pair takes its colour once every neighbour that comes
// before it has one (Jones-Plassmann), which gives the greedy colouring's
// colours exactly. One block then solves the sweeps: the pairs of a colour
// share no node, so its lanes update them at once and a barrier closes the
// colour; a pair's updates see exactly what they see in the CPU's serial sweep
// (contact/friction.cpp), so the tangential forces are the CPU's bits. Then a
// lane per node adds its pairs' friction in the CPU's order.
#include "cuda/friction.hpp"

#include <cmath>

#include "cuda/friction_impl.cuh"

#include "contact/candidate_layout.hpp"
#include "contact/friction_kernel.hpp"
#include "contact/potential_contact_kernel.hpp"
#include "cuda/device_array.cuh"
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
constexpr int32_t kNotTouching = -2; // a candidate's colour when it does not touch


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

__global__ void predict_kernel(const int32_t* halt, const double* mass, const uint8_t* constrained, const double* vx,
                               const double* vy, const double* f_pre_x, const double* f_pre_y, int32_t n, double dt,
                               double* imx, double* imy, double* wx, double* wy) {
  if (halted(halt)) return;
  const int32_t i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i >= n) return;
  friction_predict_node(mass[i], constrained[i], vx[i], vy[i], f_pre_x[i], f_pre_y[i], nullptr, nullptr, i, dt,
                        imx[i], imy[i], wx[i], wy[i]);
}

// A touching candidate's neighbours are the touching candidates of the
// entries of its six nodes (entry 6 q + k: candidate q). colour[p] is -1
// until p is coloured; a colour, once written, is final, so a lane that reads
// a neighbour's colour in the round it is written sees either -1 (and waits a
// round) or the final value.
__global__ void __launch_bounds__(kSolveThreads)
    colour_kernel(const int32_t* halt, const int32_t* node, const uint8_t* hit, const uint64_t* key,
                  const int32_t* start, const int32_t* entry, int32_t n, int32_t* colour_out, int32_t* counts) {
  if (halted(halt)) return;
  __shared__ int32_t most[kSolveThreads];
  volatile int32_t* colour = colour_out;
  for (int32_t p = threadIdx.x; p < n; p += kSolveThreads) colour[p] = hit[p] ? -1 : kNotTouching;
  __syncthreads();
  int32_t rounds = 0;
  for (;;) {
    ++rounds;
    int waiting = 0;
    for (int32_t p = threadIdx.x; p < n; p += kSolveThreads) {
      if (colour[p] != -1) continue;
      const uint64_t pp = friction_priority(key[p]);
      bool ready = true;
      // the smallest colour no neighbour before p has, 64 colours at a time
      for (int32_t base = 0; ready; base += 64) {
        uint64_t taken = 0;
        for (int k = 0; k < 6 && ready; ++k) {
          const int32_t v = node[6 * p + k];
          for (int32_t j = start[v]; j < start[v + 1]; ++j) {
            const int32_t q = entry[j] / 6;
            if (q == p) continue;
            const int32_t c = colour[q];
            if (c == kNotTouching) continue;
            if (c < 0) {
              if (coloured_before(friction_priority(key[q]), q, pp, p)) {
                ready = false;
                break;
              }
            } else if (c >= base && c < base + 64) {
              taken |= uint64_t(1) << (c - base);
            }
          }
        }
        if (ready && ~taken) {
          colour[p] = base + __ffsll((long long)~taken) - 1;
          break;
        }
      }
      if (!ready) waiting = 1;
    }
    if (!__syncthreads_or(waiting)) break;
  }
  int32_t m = -1;
  for (int32_t p = threadIdx.x; p < n; p += kSolveThreads) m = max(m, int32_t(colour[p]));
  most[threadIdx.x] = m;
  __syncthreads();
  for (int w = kSolveThreads / 2; w > 0; w /= 2) {
    if (int(threadIdx.x) < w) most[threadIdx.x] = max(most[threadIdx.x], most[threadIdx.x + w]);
    __syncthreads();
  }
  if (threadIdx.x == 0) {
    counts[0] = most[0] + 1;  // colours
    counts[1] = rounds;
  }
}

__global__ void __launch_bounds__(kSolveThreads)
    solve_kernel(const int32_t* halt, FrictionPairArrays P, int32_t n, const int32_t* colour, const int32_t* counts,
                 const uint64_t* prev_key, const double* prev_lambda, int64_t n_prev, double mu, double dt,
                 const double* imx, const double* imy, double* wx, double* wy, double* kinv, double* lambda,
                 double* power) {
  if (halted(halt)) return;
  __shared__ double shared[kSolveThreads];
  const int32_t colours = counts[0];
  for (int32_t i = threadIdx.x; i < n; i += kSolveThreads) {
    kinv[i] = P.hit[i] ? friction_inverse_mass(P.node + 6 * i, P.nc + 3 * i, P.nt + 3 * i, P.nx[i], P.ny[i], imx, imy)
                       : 0.0;
    lambda[i] = 0.0;
  }
  __syncthreads();
  // the warm start, colour by colour as the CPU pushes it
  for (int32_t c = 0; c < colours; ++c) {
    for (int32_t i = threadIdx.x; i < n; i += kSolveThreads) {
      if (colour[i] != c) continue;
      const int64_t at = find_key(prev_key, n_prev, P.key[i]);
      // NaN: a candidate that did not touch in the step before (the whole
      // step keeps the warm start per candidate, cuda/device_step.cu)
      if (at < 0 || kinv[i] == 0.0 || isnan(prev_lambda[at])) continue;
      const double lam = clamp_to_cone(prev_lambda[at], mu * P.fn[i]);
      lambda[i] = lam;
      friction_push(P.node + 6 * i, P.nc + 3 * i, P.nt + 3 * i, P.nx[i], P.ny[i], lam, dt, imx, imy, wx, wy);
    }
    __syncthreads();
  }
  for (int sweep = 0; sweep < kSweeps; ++sweep) {
    for (int32_t c = 0; c < colours; ++c) {
      for (int32_t i = threadIdx.x; i < n; i += kSolveThreads) {
        if (colour[i] != c || kinv[i] == 0.0 || P.fn[i] == 0.0) continue;
        const int32_t* node = P.node + 6 * i;
        const double* nc = P.nc + 3 * i;
        const double* nt = P.nt + 3 * i;
        const double d = friction_update(node, nc, nt, P.nx[i], P.ny[i], mu * P.fn[i], kinv[i], dt, wx, wy, lambda[i]);
        if (d != 0.0) friction_push(node, nc, nt, P.nx[i], P.ny[i], d, dt, imx, imy, wx, wy);
      }
      __syncthreads();
    }
  }
  // the power with the velocities the nodes will move with, summed in a fixed tree
  double p = 0.0;
  for (int32_t i = threadIdx.x; i < n; i += kSolveThreads) {
    if (lambda[i] != 0.0)
      p -= lambda[i] * friction_slip(P.node + 6 * i, P.nc + 3 * i, P.nt + 3 * i, P.nx[i], P.ny[i], wx, wy);
  }
  p = block_sum<kSolveThreads>(p, shared);
  if (threadIdx.x == 0) *power = p;
}

// Node i's force with its pairs' friction added in the CPU's order: pairs
// ascending, a pair's corners as the CPU visits them (contactor's j, then
// target's j, j = 0, 1, 2); entry 6 c + k names candidate c's node slot k.
__global__ void apply_kernel(const int32_t* halt, FrictionPairArrays P, const int32_t* start, const int32_t* entry,
                             const double* lambda, const double* f_pre_x, const double* f_pre_y, int32_t n, double* f_x,
                             double* f_y) {
  if (halted(halt)) return;
  const int32_t i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i >= n) return;
  double sx = f_pre_x[i], sy = f_pre_y[i];
  for (int32_t j = start[i]; j < start[i + 1]; ++j) {
    const int32_t e = entry[j], p = e / 6, k = e % 6;
    const double lam = lambda[p];
    if (lam == 0.0) continue;  // a candidate that does not touch has none
    const double tx = -P.ny[p] * lam, ty = P.nx[p] * lam;
    if (k < 3) {
      sx += P.nc[3 * p + k] * tx;
      sy += P.nc[3 * p + k] * ty;
    } else {
      sx -= P.nt[3 * p + k - 3] * tx;
      sy -= P.nt[3 * p + k - 3] * ty;
    }
  }
  f_x[i] = sx;
  f_y[i] = sy;
}

int blocks(int64_t n) { return int((n + kBlock - 1) / kBlock); }

}  // namespace

void DeviceFriction::Impl::launch() {
  if (n_cand && !pairs_given) {
    launch_kernel(pair_kernel, blocks(n_cand), kBlock, stream, halt, x.data(), y.data(), node.data(), n_cand, penalty,
                  hit.data(), nc.data(), nt.data(), nx.data(), ny.data(), fn.data());
  }
  launch_kernel(predict_kernel, blocks(n_nodes), kBlock, stream, halt, mass.data(), constrained.data(), vx.data(),
                vy.data(), f_pre_x.data(), f_pre_y.data(), n_nodes, dt, imx.data(), imy.data(), wx.data(), wy.data());
  launch_kernel(colour_kernel, 1, kSolveThreads, stream, halt, node.data(), hit.data(), key.data(), start.data(),
                entry.data(), n_cand, colour.data(), counts.data());
  launch_kernel(solve_kernel, 1, kSolveThreads, stream, halt, pairs(), n_cand, colour.data(), counts.data(),
                prev_key.data(), prev_lambda.data(), n_prev, mu, dt, imx.data(), imy.data(), wx.data(), wy.data(),
                kinv.data(), lambda.data(), power.data());
  launch_kernel(apply_kernel, blocks(n_nodes), kBlock, stream, halt, pairs(), start.data(), entry.data(), lambda.data(),
                f_pre_x.data(), f_pre_y.data(), n_nodes, f_x.data(), f_y.data());
  cuda_check(cudaGetLastError(), "kernel launch");
}


DeviceFriction::DeviceFriction(const Model& m, WarmStart warm_start) : impl_(new Impl) {
  Impl& d = *impl_;
  d.stream = new_stream();
  const Nodes& N = m.nodes();
  const ContactSolver& C = m.contact();
  const std::vector<CandidatePair>& cand = C.candidates();
  d.n_nodes = N.size();
  d.n_cand = int32_t(cand.size());
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
  d.node.upload(L.node);
  d.key.upload(L.key);
  d.start.upload(L.start);
  d.entry.upload(L.entry);
  d.hit.resize(cand.size());
  for (auto* a : {&d.nx, &d.ny, &d.fn, &d.kinv, &d.lambda}) a->resize(cand.size());
  d.nc.resize(3 * cand.size());
  d.nt.resize(3 * cand.size());
  d.colour.resize(cand.size());
  d.counts.resize(2);
  const std::vector<uint64_t>& wk = C.warm_start_keys();
  const std::vector<double>& wl = C.warm_start_forces();
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

DeviceFriction::~DeviceFriction() {
  if (impl_->stream) cudaStreamDestroy(impl_->stream);
}

void DeviceFriction::run() { impl_->launch(); }

int32_t DeviceFriction::candidates() const { return impl_->n_cand; }

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
  f.colours = counts[0];
  f.rounds = counts[1];
  return f;
}

}  // namespace engine
