// The normal contact pass on the GPU (cuda/contact_normal.hpp). The host
// lays the candidates out as friction does (contact/candidate_layout.hpp: the
// CPU's pair order, each node's entries in it); a lane per candidate
// evaluates the pair kernel, a lane per node adds its touching entries in
// list order: the CPU's sums, bit for bit.
#include "cuda/contact_normal.hpp"
#include "cuda/contact_normal_impl.cuh"

#include "contact/candidate_layout.hpp"
#include "contact/potential_contact_kernel.hpp"
#include "cuda/device_array.cuh"
#include "cuda/stream.cuh"
#include "cuda/fixed_sums.cuh"
#include "cuda/halt.cuh"
#include "cuda/launch.cuh"
#include "model/model.hpp"

namespace engine {

namespace {

constexpr int kBlock = 128;
constexpr int kSumThreads = kWideBlock;

// A pair's contact is a long chain of dependent steps in one lane (the
// overlap's three clips, then two clips per sub-triangle for six), and a
// step's few touching pairs among thousands of candidates leave the GPU
// little else to run meanwhile: the kernel took as long as one pair's chain
// (35 us a step of the paper mesh at the lease of 2026-11-30). So a group of
// kPairLanes lanes takes a candidate: its first lane tests the boxes and
// finds the overlap, six lanes then take a sub-term each (pair_sub_term:
// the owner's sub-triangle, the target's three, then the contactor's), and
// the first lane finishes the pair from them (finish_pair, which adds them in
// their order): the CPU's potential_contact_pair, bit for bit, a chain a
// third as long.
constexpr int kPairLanes = 8;  // six sub-terms; a group of eight stays within a warp
constexpr int kPairsPerBlock = kBlock / kPairLanes;

__global__ void __launch_bounds__(kBlock) pair_kernel(const int32_t* halt, const double* x, const double* y,
                                                      const int32_t* node, int64_t n, double s, double* fx,
                                                      double* fy, uint8_t* hit, double* energy,
                                                      FrictionPairOut out) {
  if (halted(halt)) return;
  __shared__ contact_kernel::Overlap overlap[kPairsPerBlock];
  __shared__ contact_kernel::SubTerm term[kPairsPerBlock][6];
  __shared__ bool touching[kPairsPerBlock];
  const int g = int(threadIdx.x) / kPairLanes, j = int(threadIdx.x) % kPairLanes;
  const int64_t p = int64_t(blockIdx.x) * kPairsPerBlock + g;
  const bool mine = p < n;
  if (j == 0) {
    bool h = false;
    if (mine) {
      const int32_t* v = node + 6 * p;  // the contactor's nodes, then the target's
      const double xa[3] = {x[v[0]], x[v[1]], x[v[2]]}, ya[3] = {y[v[0]], y[v[1]], y[v[2]]};
      const double xb[3] = {x[v[3]], x[v[4]], x[v[5]]}, yb[3] = {y[v[3]], y[v[4]], y[v[5]]};
      // (contact_candidate's two steps)
      h = !boxes_apart(xa, ya, xb, yb) && contact_kernel::overlap_of(xa, ya, xb, yb, overlap[g]);
      hit[p] = h ? 1 : 0;
      if (!h) energy[p] = 0.0;
    }
    touching[g] = h;
  }
  __syncthreads();
  const bool h = touching[g];
  const contact_kernel::Overlap& o = overlap[g];
  if (h && j < 6) contact_kernel::pair_sub_term(o, s, j, term[g][j]);
  __syncthreads();  // every lane: a barrier some lanes had left is undefined
  if (!h || j != 0) return;
  PairContact r;
  contact_kernel::finish_pair(o, [&](int i) -> const contact_kernel::SubTerm& { return term[g][i]; }, r);
  energy[p] = r.energy;
  for (int k = 0; k < 6; ++k) {
    fx[6 * p + k] = r.fx[k];
    fy[6 * p + k] = r.fy[k];
  }
  if (!out.nc) return;  // friction's pair kernel's outputs, from the same PairContact
  for (int k = 0; k < 3; ++k) {
    out.nc[3 * p + k] = r.nc[k];
    out.nt[3 * p + k] = r.nt[k];
  }
  contact_resultant(r, out.fn[p], out.nx[p], out.ny[p]);
}

// Node i's normal contact force: its entries (6 p + k) in the CPU's order,
// the touching ones only (the CPU adds nothing for the others).
// Four entries at a time, their flags and forces read together before any is
// added (in entry order: the same sums): one entry after another, each
// entry's loads waited for the last one's.
constexpr int kSumBatch = 4;
__global__ void node_sum_kernel(const int32_t* halt, const int32_t* start, const int32_t* entry, const uint8_t* hit,
                                const double* fx, const double* fy, int32_t n_nodes, double* f_con_x, double* f_con_y) {
  if (halted(halt)) return;
  const int32_t i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i >= n_nodes) return;
  double sx = 0.0, sy = 0.0;
  const int32_t end = start[i + 1];
  for (int32_t j0 = start[i]; j0 < end; j0 += kSumBatch) {
    int32_t e[kSumBatch];
    bool h[kSumBatch];
    double vx[kSumBatch], vy[kSumBatch];
    for (int u = 0; u < kSumBatch; ++u) e[u] = j0 + u < end ? entry[j0 + u] : -1;
    // a candidate that does not touch has stale forces: read, never added
    for (int u = 0; u < kSumBatch; ++u) {
      h[u] = e[u] >= 0 && hit[e[u] / 6];
      vx[u] = e[u] >= 0 ? fx[e[u]] : 0.0;
      vy[u] = e[u] >= 0 ? fy[e[u]] : 0.0;
    }
    for (int u = 0; u < kSumBatch; ++u)
      if (h[u]) {
        sx += vx[u];
        sy += vy[u];
      }
  }
  f_con_x[i] = sx;
  f_con_y[i] = sy;
}

__global__ void __launch_bounds__(kSumThreads) pair_sums_kernel(const int32_t* halt, const double* energy,
                                                                const uint8_t* hit, int64_t n, double* total,
                                                                int32_t* touching) {
  if (halted(halt)) return;
  __shared__ double shared[kSumThreads];
  double e = 0.0, h = 0.0;
  for (int64_t p = threadIdx.x; p < n; p += kSumThreads) {
    e += energy[p];
    h += hit[p];
  }
  e = block_sum<kSumThreads>(e, shared);
  h = block_sum<kSumThreads>(h, shared);  // whole numbers: exact
  if (threadIdx.x == 0) {
    *total = e;
    *touching = int32_t(h);
  }
}

int blocks(int64_t n) { return int((n + kBlock - 1) / kBlock); }

}  // namespace

void DeviceContactNormal::Impl::launch() {
  if (n_pairs) {
    launch_kernel(pair_kernel, int((n_pairs + kPairsPerBlock - 1) / kPairsPerBlock), kBlock, stream, halt, x.data(),
                  y.data(), node.data(), n_pairs, penalty,
                  fx.data(), fy.data(), hit.data(), pair_energy.data(), friction_pairs);
  }
  launch_kernel(node_sum_kernel, blocks(n_nodes), kBlock, stream, halt, start.data(), entry.data(), hit.data(),
                fx.data(), fy.data(), n_nodes, f_con_x.data(), f_con_y.data());
  if (pair_sums)
    launch_kernel(pair_sums_kernel, 1, kSumThreads, stream, halt, pair_energy.data(), hit.data(), n_pairs, total.data(),
                  touching.data());
  cuda_check(cudaGetLastError(), "kernel launch");
}


void DeviceContactNormal::Impl::size_pairs(size_t n) {
  n_pairs = int64_t(n);
  fx.resize(6 * n);
  fy.resize(6 * n);
  hit.resize(n);
  pair_energy.resize(n);
}

DeviceContactNormal::DeviceContactNormal(const Model& m) : impl_(new Impl) {
  Impl& d = *impl_;
  d.stream = new_stream();
  const Nodes& N = m.nodes();
  const std::vector<CandidatePair>& cand = m.contact().candidates();
  d.n_nodes = N.size();
  d.penalty = m.contact_params().penalty;
  CandidateLayout L;
  lay_out_candidates(cand, m.triangles().node.data(), d.n_nodes, L);
  d.node.upload(L.node);
  d.start.upload(L.start);
  d.entry.upload(L.entry);
  d.size_pairs(cand.size());
  d.x.upload(N.x);
  d.y.upload(N.y);
  d.f_con_x.resize(d.n_nodes);
  d.f_con_y.resize(d.n_nodes);
  d.total.resize(1);
  d.touching.resize(1);
}

DeviceContactNormal::~DeviceContactNormal() {
  if (impl_->stream) cudaStreamDestroy(impl_->stream);
}

void DeviceContactNormal::run() { impl_->launch(); }

int64_t DeviceContactNormal::candidates() const { return impl_->n_pairs; }

double DeviceContactNormal::time_per_run(int repeats) {
  Impl& d = *impl_;
  return mean_launch_seconds(d.stream, repeats, [&] { d.launch(); });
}

ContactNormalFields DeviceContactNormal::fields() {
  Impl& d = *impl_;
  cuda_check(cudaStreamSynchronize(d.stream), "GPU contact");
  ContactNormalFields f;
  f.f_con_x = d.f_con_x.download();
  f.f_con_y = d.f_con_y.download();
  f.energy = d.total.download()[0];
  f.touching = d.touching.download()[0];
  return f;
}

}  // namespace engine
