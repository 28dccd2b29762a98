// The body-force stage on the GPU (cuda/body_forces.hpp): the kernels are the
// CPU engine's per-triangle, per-body and per-node functions; this file holds
// only memory, launches and the fixed-order energy sum.
#include "cuda/body_forces.hpp"
#include "cuda/body_forces_impl.cuh"

#include "cuda/device_array.cuh"
#include "cuda/emulation_check.hpp"
#include "cuda/stream.cuh"
#include "cuda/fixed_sums.cuh"
#include "cuda/halt.cuh"
#include "cuda/launch.cuh"
#include "element/cst_kernel.hpp"
#include "loads/drag_kernel.hpp"
#include "loads/water_kernel.hpp"
#include "model/gather_kernel.hpp"
#include "model/model.hpp"

namespace engine {

namespace {

constexpr int kBlock = reducing_block(128);  // its per-block partial sums
// Threads per body in the quadratic drag's sums (a layer body of the paper
// mesh has ~9,000 triangles: a warp per body took ~200 us, latency-bound).
constexpr int kBodyBlock = reducing_block(256);
// The strain energy's final sum: one block of kSumThreads lanes over the
// triangle blocks' partial sums.
constexpr int kSumThreads = kWideBlock;

int blocks(int64_t n) { return int((n + kBlock - 1) / kBlock); }

// Quadratic drag, first each triangle's velocity term, stored at its place k
// in the bodies' triangle lists (so that a body's terms are contiguous) ...
__global__ void drag_terms_kernel(const int32_t* halt, BodyDragArrays a, int32_t n_tri, double* term_x,
                                  double* term_y) {
  if (halted(halt)) return;
  const int32_t k = blockIdx.x * blockDim.x + threadIdx.x;
  if (k < n_tri) drag_velocity_term(a, k, term_x[k], term_y[k]);
}

// ... then one block per body: lane l sums the body's terms l, l + kBodyBlock,
// ... in order and the lanes meet in a fixed tree, so every run gives the
// same bits (they differ from the CPU's ascending sum by round-off alone);
// the width's extremes are exact in any order.
__global__ void __launch_bounds__(kBodyBlock) drag_kernel(const int32_t* halt, BodyDragArrays a, const double* term_x,
                                                          const double* term_y, double* c_b) {
  if (halted(halt)) return;
  __shared__ double shared[kBodyBlock];
  const int32_t b = blockIdx.x;
  double Vx = 0.0, Vy = 0.0;
  for (int32_t k = a.start[b] + threadIdx.x; k < a.start[b + 1]; k += kBodyBlock) {
    Vx += term_x[k];
    Vy += term_y[k];
  }
  Vx = block_sum<kBodyBlock>(Vx, shared);
  Vy = block_sum<kBodyBlock>(Vy, shared);
  double nx, ny;
  const double speed = drag_direction(a, b, Vx, Vy, nx, ny);
  if (!(speed > 0.0) || a.surface_start[b + 1] == a.surface_start[b]) {
    if (threadIdx.x == 0) c_b[b] = 0.0;
    return;  // the whole block: speed is the same in every lane
  }
  double lo = INFINITY, hi = -INFINITY;
  for (int32_t k = a.surface_start[b] + threadIdx.x; k < a.surface_start[b + 1]; k += kBodyBlock) {
    const int32_t i = a.surface_node[k];
    const double s = a.x[i] * nx + a.y[i] * ny;
    lo = s < lo ? s : lo;
    hi = s > hi ? s : hi;
  }
  lo = block_extreme<kBodyBlock, false>(lo, shared);
  hi = block_extreme<kBodyBlock, true>(hi, shared);
  if (threadIdx.x == 0) c_b[b] = drag_constant(a.half_rho_cd, speed, lo, hi);
}

// Elements and water loads per triangle; each block's strain energies summed
// in a fixed tree into partial[block].
__global__ void __launch_bounds__(kBlock) triangle_kernel(const int32_t* halt, CstArrays e, WaterArrays w,
                                                          CornerFields load, bool damping, bool water, int32_t n_tri,
                                                          int32_t* first_inverted, double* partial) {
  if (halted(halt)) return;
  __shared__ double shared[kBlock];
  const int32_t t = blockIdx.x * blockDim.x + threadIdx.x;
  double energy = 0.0;
  if (t < n_tri) {
    bool flipped = false;
    energy = cst_triangle(e, load, damping, t, flipped);
    if (flipped) atomicMin(first_inverted, t);  // the smallest id, whatever the order
    if (water) water_triangle(w, load, t);
  }
  const double s = block_sum<kBlock>(energy, shared);
  if (threadIdx.x == 0) partial[blockIdx.x] = s;
}

__global__ void gather_kernel(const int32_t* halt, GatherArrays g, CornerFields load, int32_t n_nodes) {
  if (halted(halt)) return;
  const int32_t i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i < n_nodes) gather_node_loads<4>(g, load, i);  // four corners read at a time (gather_kernel.hpp)
}

// The partial sums in a fixed order: lane l takes partials l, l + kSumThreads, ...
__global__ void __launch_bounds__(kSumThreads) energy_sum_kernel(const int32_t* halt, const double* partial, int32_t n,
                                                                 double* total) {
  if (halted(halt)) return;
  __shared__ double shared[kSumThreads];
  const double s = strided_block_sum<kSumThreads>(partial, n, shared);
  if (threadIdx.x == 0) *total = s;
}

}  // namespace

#ifdef ICERUBBLE_CUDA_EMULATION
bool cuda_built() { return false; }  // no toolkit: the runtime is the CPU emulation's
bool cuda_emulated() { return true; }
#else
bool cuda_built() { return true; }
bool cuda_emulated() { return false; }
std::map<std::string, double> cuda_emulation_check(const std::string&) {
  throw std::runtime_error(
      "this build runs the GPU backend on a GPU: the emulation is in builds without a CUDA toolkit");
}
#endif

std::string cuda_device_name() {
  int n = 0;
  if (cudaGetDeviceCount(&n) != cudaSuccess || n == 0) {
    cudaGetLastError();  // clear it
    return "";
  }
  cudaDeviceProp p;
  cuda_check(cudaGetDeviceProperties(&p, 0), "cudaGetDeviceProperties");
  return p.name;
}

void DeviceBodyForces::Impl::launch() {
  const CstArrays e{x.data(), y.data(), vx.data(), vy.data(), node.data(), body.data(),
                    binv00.data(), binv01.data(), binv10.data(), binv11.data(), area0.data(),
                    material.data(), stress.data(), energy.data()};
  const WaterArrays w{x.data(), y.data(), node.data(), body.data(), area0.data(), body_area0.data(),
                      c_b.data(), ext.y_w, ext.rho_w * ext.g, ext.buoyancy,
                      ext.drag_on()};
  const CornerFields load{corner_load.data(), 3 * size_t(n_tri)};
  const GatherArrays g{start.data(), slot.data(), vx.data(), vy.data(),
                       mass_phys.data(), f_int_x.data(), f_int_y.data(), f_visc_x.data(),
                       f_visc_y.data(), f_buoy_y.data(), drag_k.data(), f_x.data(), f_y.data(),
                       f_coh_x.data(), f_coh_y.data(), damping, water, ext.buoyancy, ext.drag_on(),
                       ext.gravity ? ext.g : 0.0};
  if (quadratic) {
    const BodyDragArrays d{x.data(),          y.data(),          vx.data(),         vy.data(),
                           body_area0.data(), body_start.data(), body_corner.data(), body_weight.data(),
                           surf_start.data(), surf_node.data(),  0.5 * ext.rho_w * ext.C_d};
    launch_kernel(drag_terms_kernel, blocks(n_tri), kBlock, stream, halt, d, n_tri, term_x.data(), term_y.data());
    if (n_bodies) launch_kernel(drag_kernel, n_bodies, kBodyBlock, stream, halt, d, term_x.data(), term_y.data(),
                                c_b.data());
  }
  mark(0);
  if (reset_inverted) cuda_check(cudaMemsetAsync(inverted.data(), 0x7f, sizeof(int32_t), stream), "memset");
  launch_kernel(triangle_kernel, blocks(n_tri), kBlock, stream, halt, e, w, load, damping, water, n_tri,
                inverted.data(), partial.data());
  mark(1);
  launch_kernel(gather_kernel, blocks(n_nodes), kBlock, stream, halt, g, load, n_nodes);
  mark(2);
  if (sum_energy)
    launch_kernel(energy_sum_kernel, 1, kSumThreads, stream, halt, partial.data(), blocks(n_tri), total.data());
  mark(3);
  cuda_check(cudaGetLastError(), "kernel launch");
}

DeviceBodyForces::DeviceBodyForces(const Model& m) : impl_(new Impl) {
  Impl& d = *impl_;
  d.stream = new_stream();
  const Nodes& N = m.nodes();
  const Triangles& T = m.triangles();
  d.n_nodes = N.size();
  d.n_tri = T.size();
  d.n_bodies = m.n_bodies();
  d.ext = m.external();
  d.damping = m.any_damping();
  d.water = d.ext.water();
  d.quadratic = d.ext.drag_on() && d.ext.drag_model == DragModel::Quadratic;
  d.node.upload(T.node);
  d.body.upload(T.body);
  d.binv00.upload(T.binv00);
  d.binv01.upload(T.binv01);
  d.binv10.upload(T.binv10);
  d.binv11.upload(T.binv11);
  d.area0.upload(T.area0);
  d.start.upload(m.gather().start);
  d.slot.upload(m.gather().slot);
  d.mass_phys.upload(N.mass_phys);
  d.material.upload(m.element_materials());
  d.body_area0.upload(m.body_area0());
  const BodyTriangleLists& L = m.body_triangles();
  d.body_start.upload(L.start);
  d.body_corner.upload(L.corner);
  d.body_weight.upload(L.weight);
  d.surf_start.upload(L.surface_start);
  d.surf_node.upload(L.surface_node);
  // linear drag: every body's constant is c_w; none: zero
  d.c_b.upload(std::vector<double>(size_t(d.n_bodies), d.ext.drag_on() && !d.quadratic ? d.ext.c_w : 0.0));
  if (d.quadratic) {
    d.term_x.resize(d.n_tri);
    d.term_y.resize(d.n_tri);
  }
  d.stress.resize(3 * size_t(d.n_tri));
  d.corner_load.resize(3 * CornerLoad::stride * size_t(d.n_tri));
  d.energy.resize(d.n_tri);
  for (DeviceArray<double>* a : {&d.f_int_x, &d.f_int_y, &d.f_visc_x, &d.f_visc_y, &d.f_buoy_y, &d.drag_k,
                                 &d.f_x, &d.f_y, &d.f_coh_x, &d.f_coh_y})
    a->resize(d.n_nodes);
  d.total.resize(1);
  d.partial.resize(size_t(blocks(d.n_tri)));
  d.inverted.resize(1);
  upload_state(m);
}

DeviceBodyForces::~DeviceBodyForces() {
  for (cudaEvent_t& e : impl_->stage_end)
    if (e) cudaEventDestroy(e);
  if (impl_->graph) cudaGraphExecDestroy(impl_->graph);
  if (impl_->stream) cudaStreamDestroy(impl_->stream);
}

void DeviceBodyForces::upload_state(const Model& m) {
  const Nodes& N = m.nodes();
  if (N.size() != impl_->n_nodes || m.triangles().size() != impl_->n_tri)
    throw std::runtime_error("GPU: the model's mesh changed since it was copied (bond splits): make a new DeviceBodyForces");
  impl_->x.upload(N.x);
  impl_->y.upload(N.y);
  impl_->vx.upload(N.vx);
  impl_->vy.upload(N.vy);
}

void DeviceBodyForces::run() { impl_->launch(); }

double DeviceBodyForces::time_per_run(int repeats) {
  Impl& d = *impl_;
  if (repeats < 1) throw std::invalid_argument("repeats must be at least 1");  // before the capture
  if (!d.graph) {
    cudaGraph_t g;
    cuda_check(cudaStreamBeginCapture(d.stream, cudaStreamCaptureModeThreadLocal), "graph capture");
    d.launch();
    cuda_check(cudaStreamEndCapture(d.stream, &g), "graph capture");
    cuda_check(cudaGraphInstantiate(&d.graph, g, 0), "graph instantiate");
    cudaGraphDestroy(g);
  }
  return mean_launch_seconds(d.stream, repeats,
                             [&] { cuda_check(cudaGraphLaunch(d.graph, d.stream), "graph launch"); });
}

std::vector<double> DeviceBodyForces::stage_times(int repeats) {
  Impl& d = *impl_;
  if (repeats < 1) throw std::invalid_argument("repeats must be at least 1");
  cudaEvent_t begin;
  cuda_check(cudaEventCreate(&begin), "event");
  for (cudaEvent_t& e : d.stage_end)
    if (!e) cuda_check(cudaEventCreate(&e), "event");
  std::vector<double> total(4, 0.0);
  d.timing_stages = true;
  for (int r = 0; r < repeats + 3; ++r) {  // the first 3 warm up
    cuda_check(cudaEventRecord(begin, d.stream), "event");
    d.launch();
    cuda_check(cudaEventSynchronize(d.stage_end[3]), "event");
    float ms = 0.0f;
    for (int k = 0; k < 4; ++k) {
      cuda_check(cudaEventElapsedTime(&ms, k ? d.stage_end[k - 1] : begin, d.stage_end[k]), "event");
      if (r >= 3) total[k] += 1e-3 * double(ms) / repeats;
    }
  }
  d.timing_stages = false;
  cudaEventDestroy(begin);
  return total;
}

BodyForceFields DeviceBodyForces::fields() {
  Impl& d = *impl_;
  cuda_check(cudaStreamSynchronize(d.stream), "GPU step");
  BodyForceFields f;
  f.f_int_x = d.f_int_x.download();
  f.f_int_y = d.f_int_y.download();
  f.f_visc_x = d.f_visc_x.download();
  f.f_visc_y = d.f_visc_y.download();
  f.f_buoy_y = d.f_buoy_y.download();
  f.drag_k = d.drag_k.download();
  f.f_x = d.f_x.download();
  f.f_y = d.f_y.download();
  f.stress = d.stress.download();
  f.energy = d.energy.download();
  f.elastic_energy = d.total.download()[0];
  const int32_t inv = d.inverted.download()[0];
  f.first_inverted = inv == 0x7f7f7f7f ? -1 : inv;
  return f;
}

}  // namespace engine
