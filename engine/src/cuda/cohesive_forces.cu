// The cohesive forces on the GPU (cuda/cohesive_forces.hpp): cohesive_pair_step
// per opened pair, then per node the sum of its pairs' forces in ascending
// pair order (the CPU's scatter order, so the same bits), and the energy
// terms in a fixed tree.
#include "cuda/cohesive_forces.hpp"

#include <algorithm>

#include "bonds/cohesive_pair_kernel.hpp"
#include "bonds/crack_closure_kernel.hpp"
#include "cuda/cohesive_forces_impl.cuh"
#include "cuda/device_array.cuh"
#include "cuda/fixed_sums.cuh"
#include "cuda/stream.cuh"
#include "cuda/halt.cuh"
#include "cuda/launch.cuh"
#include "model/model.hpp"

namespace engine {

namespace {

constexpr int kBlock = reducing_block(128);  // its per-block partial sums
constexpr int kTerms = 3;  // work, stored, dissipation
constexpr int kSumThreads = kWideBlock;

__global__ void __launch_bounds__(kBlock)
    pair_kernel(const int32_t* halt, CohesivePairArrays a, const int32_t* open, int32_t n,
                cohesive_law::ForceDirection dir, double dt, double* fpx, double* fpy, double* delta_m, int8_t* failed,
                int8_t* mode, double* partial, int32_t n_blocks) {
  if (halted(halt)) return;
  __shared__ double shared[kBlock];
  const int32_t j = blockIdx.x * blockDim.x + threadIdx.x;
  CohesivePairStep r;
  if (j < n) {
    r = cohesive_pair_step(a, open[j], dir, dt);
    fpx[j] = r.fpx;
    fpy[j] = r.fpy;
    delta_m[j] = r.delta_m;
    failed[j] = r.failed;
    mode[j] = r.mode;
  }
  const double terms[kTerms] = {r.work, r.stored, r.dissipation};
  #pragma unroll
  for (int k = 0; k < kTerms; ++k) {
    const double s = block_sum<kBlock>(terms[k], shared);
    if (threadIdx.x == 0) partial[size_t(k) * n_blocks + blockIdx.x] = s;
  }
}

// The same, in a committed step: the pair's history and any full failure
// written as FreezeBonds::apply(commit) writes them (each lane its own pair).
// A pair that failed in an earlier step of these stages stays in their list
// (the whole step makes no stage again for a failure) and is passed over, as
// the CPU's list, which it has left, passes over it: no force (a +0 in its
// nodes' sums), no energy terms, its history and failure record kept.
__global__ void __launch_bounds__(kBlock)
    committed_pair_kernel(const int32_t* halt, CohesivePairArrays a, CohesiveHistory h, const int32_t* open, int32_t n,
                          cohesive_law::ForceDirection dir, double dt, const double* time, double* fpx, double* fpy,
                          double* partial, int32_t n_blocks) {
  if (halted(halt)) return;
  __shared__ double shared[kBlock];
  const int32_t j = blockIdx.x * blockDim.x + threadIdx.x;
  CohesivePairStep r;
  if (j < n) {
    const int32_t k = open[j];
    if (h.pair_state[k] != PairState::failed) {
      r = cohesive_pair_step(a, k, dir, dt);
      commit_pair_step(h, a, k, r, *time);
    }
    fpx[j] = r.fpx;
    fpy[j] = r.fpy;
  }
  const double terms[kTerms] = {r.work, r.stored, r.dissipation};
  #pragma unroll
  for (int k = 0; k < kTerms; ++k) {
    const double s = block_sum<kBlock>(terms[k], shared);
    if (threadIdx.x == 0) partial[size_t(k) * n_blocks + blockIdx.x] = s;
  }
}

// Each node's opened pairs' forces summed (cohesive_node_sum).
__global__ void node_kernel(const int32_t* halt, CohesiveNodeArrays a, int32_t n) {
  if (halted(halt)) return;
  const int32_t i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i < n) cohesive_node_sum(a, i);
}

// Each node's crack-closure forces added to its contact force (crack_closure_node).
__global__ void closure_kernel(const int32_t* halt, CohesiveNodeArrays a, int32_t n) {
  if (halted(halt)) return;
  const int32_t i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i < n) crack_closure_node(a, i);
}

// Each node's pairs of the list `pairs` (ascending) in list order: node i's
// entries are entry[start[i]..start[i + 1]), entry 2 j for pairs[j]'s + node,
// 2 j + 1 for its - node (a counting sort).
void pairs_by_node(const std::vector<int32_t>& pairs, const int32_t* node_plus, const int32_t* node_minus, size_t nn,
                   std::vector<int32_t>& start, std::vector<int32_t>& entry) {
  start.assign(nn + 1, 0);
  entry.assign(2 * pairs.size(), 0);
  for (const int32_t k : pairs) {
    ++start[size_t(node_plus[k]) + 1];
    ++start[size_t(node_minus[k]) + 1];
  }
  for (size_t i = 0; i < nn; ++i) start[i + 1] += start[i];
  std::vector<int32_t> fill(start.begin(), start.end() - 1);
  for (size_t j = 0; j < pairs.size(); ++j) {
    entry[size_t(fill[size_t(node_plus[pairs[j]])]++)] = int32_t(2 * j);
    entry[size_t(fill[size_t(node_minus[pairs[j]])]++)] = int32_t(2 * j + 1);
  }
}

}  // namespace

int DeviceCohesiveForces::Impl::n_blocks() const { return n_open ? (n_open + kBlock - 1) / kBlock : 1; }

CohesivePairArrays DeviceCohesiveForces::Impl::arrays(const double* at_x, const double* at_y, const double* at_vx,
                                                     const double* at_vy, const double* at_f_x, const double* at_f_y,
                                                     const double* at_f_con_x, const double* at_f_con_y) {
  return {at_x,        at_y,         at_vx,           at_vy,           mass.data(),     at_f_x,
          at_f_y,      at_f_con_x,   at_f_con_y,      pair_point.data(), node_plus.data(), node_minus.data(),
          fnx.data(),  fny.data(),   f0.data(),       delta_f.data(),  delta_m_in.data(), f_n_prev.data(),
          f_t_prev.data(), d_n_prev.data(), d_t_prev.data(), beta.data()};
}

CohesiveHistory DeviceCohesiveForces::Impl::history() {
  return {delta_m_in.data(), f_n_prev.data(), f_t_prev.data(), d_n_prev.data(), d_t_prev.data(), pair_state.data(),
          pair_mode.data(),  t_fail.data(),   x_fail.data(),   y_fail.data(),   dn_fail.data(),  dt_fail.data()};
}

CohesiveNodeArrays DeviceCohesiveForces::Impl::node_arrays(const CohesivePairArrays& a, double* at_f_con_x,
                                                           double* at_f_con_y) {
  return {start.data(),        entry.data(),         fpx.data(),           fpy.data(),    f_coh_x.data(),
          f_coh_y.data(),      a.x,                  a.y,                  node_plus.data(), node_minus.data(),
          fnx.data(),          fny.data(),           penalty,              closure_pair.data(), closure_start.data(),
          closure_entry.data(), at_f_con_x,          at_f_con_y};
}

void DeviceCohesiveForces::Impl::launch() {
  const CohesivePairArrays a = arrays(x.data(), y.data(), vx.data(), vy.data(), f_x.data(), f_y.data(),
                                      f_con_x.data(), f_con_y.data());
  launch_kernel(pair_kernel, n_blocks(), kBlock, stream, halt, a, open.data(), n_open, dir, dt, fpx.data(), fpy.data(),
                delta_m.data(), failed.data(), mode.data(), partial.data(), n_blocks());
  launch_kernel(node_kernel, (n_nodes + kBlock - 1) / kBlock, kBlock, stream, halt,
                node_arrays(a, f_con_x.data(), f_con_y.data()), n_nodes);
  launch_kernel(term_sums_kernel<kSumThreads>, kTerms, kSumThreads, stream, halt, partial.data(), n_blocks(),
                sums.data());
  cuda_check(cudaGetLastError(), "kernel launch");
}

void DeviceCohesiveForces::Impl::launch_committed(const CohesivePairArrays& a, const double* time, double* f_con_x,
                                                   double* f_con_y, bool node_pass, bool term_sums) {
  launch_kernel(committed_pair_kernel, n_blocks(), kBlock, stream, halt, a, history(), open.data(), n_open, dir, dt,
                time, fpx.data(), fpy.data(), partial.data(), n_blocks());
  if (term_sums)
    launch_kernel(term_sums_kernel<kSumThreads>, kTerms, kSumThreads, stream, halt, partial.data(), n_blocks(),
                  sums.data());
  if (node_pass) {
    const CohesiveNodeArrays na = node_arrays(a, f_con_x, f_con_y);
    const int nb = (n_nodes + kBlock - 1) / kBlock;
    launch_kernel(node_kernel, nb, kBlock, stream, halt, na, n_nodes);
    launch_kernel(closure_kernel, nb, kBlock, stream, halt, na, n_nodes);
  }
  cuda_check(cudaGetLastError(), "kernel launch");
}

DeviceCohesiveForces::DeviceCohesiveForces(const Model& m) : impl_(new Impl) {
  Impl& d = *impl_;
  d.stream = new_stream();
  const FreezeBonds& B = m.bonds();
  const CohesivePairArrays h = B.pair_arrays(m);
  const Nodes& N = m.nodes();
  const std::vector<int32_t>& open = B.open_pairs();
  d.n_nodes = N.size();
  d.n_open = int32_t(open.size());
  d.dt = m.dt();
  d.dir = B.params().direction;
  const size_t nn = size_t(d.n_nodes), nk = size_t(B.n_pairs()), np = size_t(B.n_points());
  d.x.upload(h.x, nn);
  d.y.upload(h.y, nn);
  d.vx.upload(h.vx, nn);
  d.vy.upload(h.vy, nn);
  d.mass.upload(h.mass, nn);
  d.f_x.upload(h.f_x, nn);
  d.f_y.upload(h.f_y, nn);
  d.f_con_x.upload(h.f_con_x, nn);
  d.f_con_y.upload(h.f_con_y, nn);
  d.pair_point.upload(h.pair_point, nk);
  d.node_plus.upload(h.node_plus, nk);
  d.node_minus.upload(h.node_minus, nk);
  d.fnx.upload(h.fnx, nk);
  d.fny.upload(h.fny, nk);
  d.f0.upload(h.f0, nk);
  d.delta_f.upload(h.delta_f, nk);
  d.delta_m_in.upload(h.delta_m, nk);
  d.f_n_prev.upload(h.f_n_prev, nk);
  d.f_t_prev.upload(h.f_t_prev, nk);
  d.d_n_prev.upload(h.d_n_prev, nk);
  d.d_t_prev.upload(h.d_t_prev, nk);
  d.beta.upload(h.beta, np);
  d.open.upload(open);
  const BondState& st = B.state();
  d.pair_state.upload(st.pair_state);
  d.pair_mode.upload(st.mode);
  d.t_fail.upload(st.t_fail);
  d.x_fail.upload(st.x_fail);
  d.y_fail.upload(st.y_fail);
  d.dn_fail.upload(st.dn_fail);
  d.dt_fail.upload(st.dt_fail);
  // the crack closure's pairs: the split ones (opened or failed), ascending, by node
  d.penalty = m.contact_params().penalty;
  const std::vector<int32_t>& closed = B.closing_pairs();
  std::vector<int32_t> start, entry;
  pairs_by_node(closed, h.node_plus, h.node_minus, nn, start, entry);
  d.closure_pair.upload(closed);
  d.closure_start.upload(start);
  d.closure_entry.upload(entry);
  // the opened pairs by node
  pairs_by_node(open, h.node_plus, h.node_minus, nn, start, entry);
  d.start.upload(start);
  d.entry.upload(entry);
  const size_t no = std::max<size_t>(1, open.size());
  d.fpx.resize(no);
  d.fpy.resize(no);
  d.delta_m.resize(no);
  d.failed.resize(no);
  d.mode.resize(no);
  d.f_coh_x.resize(nn);
  d.f_coh_y.resize(nn);
  d.partial.resize(size_t(kTerms) * d.n_blocks());
  d.sums.resize(kTerms);
}

DeviceCohesiveForces::~DeviceCohesiveForces() {
  if (impl_->stream) cudaStreamDestroy(impl_->stream);
}

void DeviceCohesiveForces::run() { impl_->launch(); }

int32_t DeviceCohesiveForces::open_pairs() const { return impl_->n_open; }

double DeviceCohesiveForces::time_per_run(int repeats) {
  Impl& d = *impl_;
  return mean_launch_seconds(d.stream, repeats, [&] { d.launch(); });
}

CohesiveForceFields DeviceCohesiveForces::fields() {
  Impl& d = *impl_;
  cuda_check(cudaStreamSynchronize(d.stream), "GPU cohesive forces");
  CohesiveForceFields f;
  f.f_coh_x = d.f_coh_x.download();
  f.f_coh_y = d.f_coh_y.download();
  const size_t n = size_t(d.n_open);
  f.fpx = d.fpx.download();
  f.fpy = d.fpy.download();
  f.delta_m = d.delta_m.download();
  f.failed = d.failed.download();
  f.mode = d.mode.download();
  for (auto* v : {&f.fpx, &f.fpy, &f.delta_m}) v->resize(n);
  f.failed.resize(n);
  f.mode.resize(n);
  const std::vector<double> s = d.sums.download();
  f.work = s[0];
  f.stored = s[1];
  f.dissipation = s[2];
  return f;
}

}  // namespace engine
