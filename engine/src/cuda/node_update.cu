// The node update on the GPU (cuda/node_update.hpp): update_node per node,
// each block's NodeWork terms summed in a fixed tree, then the blocks'
// partial sums in a fixed order.
#include "cuda/node_update.hpp"
#include "cuda/node_update_impl.cuh"

#include "cuda/device_array.cuh"
#include "cuda/stream.cuh"
#include "cuda/fixed_sums.cuh"
#include "cuda/halt.cuh"
#include "cuda/launch.cuh"
#include "model/model.hpp"
#include "contact/broad_phase.hpp"
#include "model/reach_kernel.hpp"
#include "model/update_kernel.hpp"

namespace engine {

namespace {

constexpr int kBlock = reducing_block(128);  // its per-block partial sums
constexpr int kTerms = 13;  // NodeWork's fields
constexpr int kSumThreads = kWideBlock;

__global__ void __launch_bounds__(kBlock) update_kernel(const int32_t* halt, UpdateArrays a, int32_t n, double* partial,
                                                        int32_t n_blocks, UpdateTests t, UpdateBoundary b) {
  if (halted(halt)) return;
  __shared__ double shared[kBlock];
  const int32_t i = blockIdx.x * blockDim.x + threadIdx.x;
  NodeWork w{};
  if (i < n) {
    if (b.x) {  // the components are apart: x, then y, as the CPU sets them
      if (b.x[i] >= 0) prescribe_component(b.cx, i, b.values[b.x[i]], b.inv_dt);
      if (b.y[i] >= 0) prescribe_component(b.cy, i, b.values[b.y[i]], b.inv_dt);
    }
    w = update_node(a, i);
    // any lane that finds one writes the same 1
    if (t.moved && t.on_surface[i] && moved_past_skin(a.x[i], a.y[i], t.list_x[i], t.list_y[i], t.skin))
      *t.moved = 1;
    if (t.reach_moved && *t.reach_now &&
        moved_past_reach(a.x[i], a.y[i], t.reach_x[i], t.reach_y[i], t.reach_half))
      *t.reach_moved = 1;
  }
  const double terms[kTerms] = {w.kinetic2_new, w.kinetic2_old, w.viscous, w.local_damping, w.contact,
                                w.friction, w.cohesive, w.gravity, w.buoyancy, w.drag, w.boundary,
                                w.elastic_new, w.elastic_old};
  #pragma unroll
  for (int k = 0; k < kTerms; ++k) {
    const double s = block_sum<kBlock>(terms[k], shared);
    if (threadIdx.x == 0) partial[size_t(k) * n_blocks + blockIdx.x] = s;
  }
}

}  // namespace

int DeviceNodeUpdate::Impl::n_blocks() const { return (n + kBlock - 1) / kBlock; }

void DeviceNodeUpdate::Impl::launch(const UpdateTests& tests, const UpdateBoundary& boundary, bool term_sums) {
  const UpdateArrays a{x.data(),       y.data(),       vx.data(),       vy.data(),      mass.data(),
                       mass_phys.data(), f_x.data(),   f_y.data(),      f_pre_x.data(), f_pre_y.data(),
                       f_int_x.data(), f_int_y.data(), f_visc_x.data(), f_visc_y.data(), f_con_x.data(),
                       f_con_y.data(), f_coh_x.data(), f_coh_y.data(), f_buoy_y.data(), drag_k.data(),
                       r_x.data(),     r_y.data(),     v_bc_x.data(),   v_bc_y.data(),  constrained.data(),
                       dt,             g,              alpha};
  launch_kernel(update_kernel, n_blocks(), kBlock, stream, halt, a, n, partial.data(), n_blocks(), tests, boundary);
  if (term_sums)
    launch_kernel(term_sums_kernel<kSumThreads>, kTerms, kSumThreads, stream, halt, partial.data(), n_blocks(),
                  sums.data());
  cuda_check(cudaGetLastError(), "kernel launch");
}

DeviceNodeUpdate::DeviceNodeUpdate(const Model& m) : impl_(new Impl) {
  Impl& d = *impl_;
  d.stream = new_stream();
  const Nodes& N = m.nodes();
  d.n = N.size();
  d.dt = m.dt();
  d.g = m.external().gravity ? m.external().g : 0.0;
  d.alpha = m.local_damping();
  d.x.upload(N.x);
  d.y.upload(N.y);
  d.vx.upload(N.vx);
  d.vy.upload(N.vy);
  d.mass.upload(N.mass);
  d.mass_phys.upload(N.mass_phys);
  d.f_x.upload(N.f_x);
  d.f_y.upload(N.f_y);
  d.f_pre_x.upload(N.f_pre_x);
  d.f_pre_y.upload(N.f_pre_y);
  d.f_int_x.upload(N.f_int_x);
  d.f_int_y.upload(N.f_int_y);
  d.f_visc_x.upload(N.f_visc_x);
  d.f_visc_y.upload(N.f_visc_y);
  d.f_con_x.upload(N.f_con_x);
  d.f_con_y.upload(N.f_con_y);
  d.f_coh_x.upload(N.f_coh_x);
  d.f_coh_y.upload(N.f_coh_y);
  d.f_buoy_y.upload(N.f_buoy_y);
  d.drag_k.upload(N.drag_k);
  d.r_x.upload(N.r_x);
  d.r_y.upload(N.r_y);
  d.v_bc_x.upload(N.v_bc_x);
  d.v_bc_y.upload(N.v_bc_y);
  d.constrained.upload(N.constrained);
  d.partial.resize(size_t(kTerms) * d.n_blocks());
  d.sums.resize(kTerms);
}

DeviceNodeUpdate::~DeviceNodeUpdate() {
  if (impl_->stream) cudaStreamDestroy(impl_->stream);
}

void DeviceNodeUpdate::run() { impl_->launch(); }

double DeviceNodeUpdate::time_per_run(int repeats) {
  Impl& d = *impl_;
  return mean_launch_seconds(d.stream, repeats, [&] { d.launch(); });
}

NodeUpdateFields DeviceNodeUpdate::fields() {
  Impl& d = *impl_;
  cuda_check(cudaStreamSynchronize(d.stream), "GPU update");
  NodeUpdateFields f;
  f.x = d.x.download();
  f.y = d.y.download();
  f.vx = d.vx.download();
  f.vy = d.vy.download();
  f.sums = d.sums.download();
  return f;
}

}  // namespace engine
