// The bond check on the GPU (cuda/bond_check.hpp): bond_point_ratio per
// intact point, then the plan (ascending points at the criterion) on the host.
#include "cuda/bond_check.hpp"

#include <cmath>

#include "bonds/bond_check_kernel.hpp"
#include "cuda/bond_check_impl.cuh"
#include "cuda/device_array.cuh"
#include "cuda/stream.cuh"
#include "cuda/halt.cuh"
#include "cuda/launch.cuh"
#include "model/model.hpp"

namespace engine {

namespace {

constexpr int kBlock = 128;

__global__ void check_kernel(const int32_t* halt, BondCheckArrays a, const int32_t* points, int32_t n, double mu,
                             double* ratio) {
  if (halted(halt)) return;
  const int32_t j = blockIdx.x * blockDim.x + threadIdx.x;
  if (j < n) ratio[points[j]] = bond_point_ratio(a, points[j], mu);
}

// FreezeBonds::check's loop body for one intact point in a committed step:
// the same screening, the same flags; a point at the criterion sets *split
// (the step is then the model's, whose check makes the plan).
__global__ void screened_check_kernel(const int32_t* halt, BondCheckArrays a, const int32_t* points, int32_t n,
                                      double mu, const int64_t* step_at, int32_t k, double frac, const int8_t* near,
                                      int8_t* near_next, int32_t* split, unsigned long long* evaluated) {
  if (halted(halt)) return;
  const int32_t j = blockIdx.x * blockDim.x + threadIdx.x;
  if (j >= n) return;
  const int32_t p = points[j];
  const int64_t step = *step_at;
  if (k > 1 && !near[p] && (step + p) % k != 0) {
    near_next[p] = near[p];
    return;
  }
  atomicAdd(evaluated, 1ULL);  // an integer count: the same in any order
  const double r = bond_point_ratio(a, p, mu);
  near_next[p] = r >= frac;
  if (r >= 1.0) *split = 1;  // any lane: the same 1
}

template <class T>
void upload(DeviceArray<T>& d, const T* h, size_t n) {
  d.upload(h, n);
}

}  // namespace

BondCheckArrays DeviceBondCheck::Impl::arrays(const double* at_x, const double* at_y, const double* at_stress) {
  return {at_x,         at_y,          start.data(),    slot.data(),     at_stress,
          area0.data(), point_node.data(), first_pair.data(), n_pairs_of.data(),
          sigma_cr.data(), tau_cr.data(), beta.data(),     frame_p.data(),  frame_q.data(),
          d0x.data(),   d0y.data(),    n0x.data(),      n0y.data(),      tn.data(),
          tt.data()};
}

void DeviceBondCheck::Impl::launch() {
  if (n_intact)
    launch_kernel(check_kernel, (n_intact + kBlock - 1) / kBlock, kBlock, stream, halt,
                  arrays(x.data(), y.data(), stress.data()), intact.data(), n_intact, mu, ratio.data());
  cuda_check(cudaGetLastError(), "kernel launch");
}

void DeviceBondCheck::Impl::launch_screened(const double* at_x, const double* at_y, const double* at_stress,
                                            const int64_t* step) {
  if (n_intact)
    launch_kernel(screened_check_kernel, (n_intact + kBlock - 1) / kBlock, kBlock, stream, halt,
                  arrays(at_x, at_y, at_stress), intact.data(), n_intact, mu, step, screen_interval, screen_fraction,
                  near.data(), near_next.data(), split.data(), evaluated.data());
  cuda_check(cudaGetLastError(), "kernel launch");
}

DeviceBondCheck::DeviceBondCheck(const Model& m) : impl_(new Impl) {
  Impl& d = *impl_;
  d.stream = new_stream();
  const FreezeBonds& B = m.bonds();
  const BondCheckArrays h = B.check_arrays(m);
  const Nodes& N = m.nodes();
  const Triangles& T = m.triangles();
  d.n_points = B.n_points();
  d.n_pairs = B.n_pairs();
  d.n_intact = int32_t(B.intact_points().size());
  d.mu = B.mu(m);
  const size_t nn = size_t(N.size()), nt = size_t(T.size()), np = size_t(d.n_points), nk = size_t(d.n_pairs);
  upload(d.x, h.x, nn);
  upload(d.y, h.y, nn);
  upload(d.start, h.gather_start, nn + 1);
  upload(d.slot, h.gather_slot, size_t(m.gather().start[nn]));
  upload(d.stress, h.stress, 3 * nt);
  upload(d.area0, h.area0, nt);
  upload(d.point_node, h.point_node, np);
  upload(d.first_pair, h.first_pair, np);
  upload(d.n_pairs_of, h.n_pairs, np);
  upload(d.sigma_cr, h.sigma_cr, np);
  upload(d.tau_cr, h.tau_cr, np);
  upload(d.beta, h.beta, np);
  upload(d.frame_p, h.frame_p, nk);
  upload(d.frame_q, h.frame_q, nk);
  upload(d.d0x, h.d0x, nk);
  upload(d.d0y, h.d0y, nk);
  upload(d.n0x, h.n0x, nk);
  upload(d.n0y, h.n0y, nk);
  d.tn.upload(std::vector<double>(nk, NAN));
  d.tt.upload(std::vector<double>(nk, NAN));
  d.ratio.upload(std::vector<double>(np, NAN));
  d.intact.upload(B.intact_points());
  d.screen_interval = B.params().screen_interval;
  d.screen_fraction = B.params().screen_fraction;
  d.near.upload(B.state().near);
  d.near_next.upload(B.state().near);  // a point not checked keeps its flag in either
  d.split.resize(1);
  d.evaluated.resize(1);
}

DeviceBondCheck::~DeviceBondCheck() {
  if (impl_->stream) cudaStreamDestroy(impl_->stream);
}

void DeviceBondCheck::run() { impl_->launch(); }

double DeviceBondCheck::time_per_run(int repeats) {
  Impl& d = *impl_;
  return mean_launch_seconds(d.stream, repeats, [&] { d.launch(); });
}

BondCheckFields DeviceBondCheck::fields() {
  Impl& d = *impl_;
  cuda_check(cudaStreamSynchronize(d.stream), "GPU bond check");
  BondCheckFields f;
  f.ratio = d.ratio.download();
  f.tn = d.tn.download();
  f.tt = d.tt.download();
  for (int32_t p = 0; p < d.n_points; ++p)
    if (f.ratio[p] >= 1.0) f.plan.push_back(p);
  return f;
}

}  // namespace engine
