// The contact candidate list searched on the GPU (cuda/broad_phase.hpp).
//
// The CPU's search (contact/broad_phase.cpp) in passes over the surface
// triangles: their bounding boxes and the grid's extremes (block trees of
// min and max, exact in any order), the grid sized by the CPU's function
// (grid_shape), each triangle binned by its grown box's lower-left corner
// and the triangles sorted by cell (stable: the CPU's counting sort's order),
// then a lane per sorted triangle walks its cell after it and the four
// forward neighbours with the CPU's pair test (candidate_pair): once to
// count, once, after a prefix sum of the counts, to write. So the GPU finds
// the CPU's candidates; sorted by their keys ((contactor, target), unique)
// they are the CPU's layout (lay_out_candidates): six nodes each, each node's
// entries in candidate order (a stable sort by node), a node's first entry by
// a binary search. No atomics: one result every run.
#include "cuda/broad_phase.hpp"
#include "cuda/broad_phase_impl.cuh"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <stdexcept>
#include <string>

#include "common/stopwatch.hpp"
#include "contact/friction_kernel.hpp"  // friction_pair_key
#include "cuda/device_sort.cuh"
#include "cuda/fixed_sums.cuh"
#include "cuda/launch.cuh"
#include "cuda/stream.cuh"
#include "model/model.hpp"

namespace engine {

namespace {

constexpr int kBlock = 128;
constexpr int kReduceBlock = reducing_block(128);
constexpr int kWide = kWideBlock;
// the extremes' per-block partials, by name, and which are maxima (the
// largest extent and lower-left corner) and which minima (the smallest
// lower-left corner, the first bad triangle)
enum Extreme { e_ext, e_xmin, e_ymin, e_xmax, e_ymax, e_bad, n_extremes };
__device__ inline bool is_max(int k) { return k == e_ext || k == e_xmax || k == e_ymax; }

int blocks(int64_t n, int block = kBlock) { return int((n + block - 1) / block); }

__device__ inline bool finite(double v) { return fabs(v) <= DBL_MAX; }  // false for NaN too

// The number of bits that hold every value below n.
int bits_below(int64_t n) {
  int b = 1;
  while (b < 63 && (int64_t(1) << b) < n) ++b;
  return b;
}

// Each surface triangle's box, and per block its largest extent, the
// smallest and largest lower-left corners and its first triangle with a
// non-finite corner (the CPU reports the first in the list).
__global__ void __launch_bounds__(kReduceBlock)
    box_kernel(const int32_t* surface, const int32_t* tri, const double* x, const double* y, int32_t n, double* bx0,
               double* by0, double* bx1, double* by1, double* partial, int32_t n_blocks) {
  __shared__ double shared[kReduceBlock];
  const int32_t i = blockIdx.x * blockDim.x + threadIdx.x;
  double ext = -INFINITY, lxm = INFINITY, lym = INFINITY, lxM = -INFINITY, lyM = -INFINITY, bad = INFINITY;
  if (i < n) {
    const int32_t* v = tri + 3 * int64_t(surface[i]);
    const double x0 = x[v[0]], x1 = x[v[1]], x2 = x[v[2]];
    const double y0 = y[v[0]], y1 = y[v[1]], y2 = y[v[2]];
    const double lx = fmin(x0, fmin(x1, x2)), ux = fmax(x0, fmax(x1, x2));
    const double ly = fmin(y0, fmin(y1, y2)), uy = fmax(y0, fmax(y1, y2));
    bx0[i] = lx;
    bx1[i] = ux;
    by0[i] = ly;
    by1[i] = uy;
    if (finite(x0) && finite(x1) && finite(x2) && finite(y0) && finite(y1) && finite(y2)) {
      ext = fmax(ux - lx, uy - ly);
      lxm = lxM = lx;
      lym = lyM = ly;
    } else {
      bad = double(i);
    }
  }
  const double v[n_extremes] = {ext, lxm, lym, lxM, lyM, bad};
  for (int k = 0; k < n_extremes; ++k) {
    const double e = is_max(k) ? block_extreme<kReduceBlock, true>(v[k], shared)
                               : block_extreme<kReduceBlock, false>(v[k], shared);
    if (threadIdx.x == 0) partial[size_t(k) * n_blocks + blockIdx.x] = e;
  }
}

// The partials reduced, the grid sized as the CPU sizes it; *first_bad the
// first triangle with a non-finite corner (-1: none).
__global__ void __launch_bounds__(kWide)
    grid_kernel(const double* partial, int32_t n_blocks, int32_t n, double skin_fraction, GridShape* grid,
                int32_t* first_bad) {
  __shared__ double shared[kWide];
  double r[n_extremes];
  for (int k = 0; k < n_extremes; ++k) {
    double e = is_max(k) ? -INFINITY : INFINITY;
    for (int32_t b = threadIdx.x; b < n_blocks; b += kWide) {
      const double p = partial[size_t(k) * n_blocks + b];
      e = is_max(k) ? fmax(e, p) : fmin(e, p);
    }
    r[k] = is_max(k) ? block_extreme<kWide, true>(e, shared) : block_extreme<kWide, false>(e, shared);
  }
  if (threadIdx.x != 0) return;
  *first_bad = finite(r[e_bad]) ? int32_t(r[e_bad]) : -1;
  if (*first_bad >= 0) return;
  *grid = grid_shape(n, r[e_ext], r[e_xmin], r[e_ymin], r[e_xmax], r[e_ymax], skin_fraction);
}

// Each box grown by the skin, binned by its lower-left corner.
__global__ void bin_kernel(const GridShape* grid, int32_t n, double* bx0, double* by0, double* bx1, double* by1,
                           uint32_t* cell, int32_t* index) {
  const int32_t i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i >= n) return;
  const GridShape g = *grid;
  bx0[i] -= g.skin;
  by0[i] -= g.skin;
  bx1[i] += g.skin;
  by1[i] += g.skin;
  cell[i] = uint32_t(cell_of(g, bx0[i], by0[i]));
  index[i] = i;
}

// The first of the n sorted values not below v.
__device__ inline int32_t lower_bound(const uint32_t* sorted, int32_t n, int64_t v) {
  int32_t lo = 0, hi = n;
  while (lo < hi) {
    const int32_t mid = lo + (hi - lo) / 2;
    if (int64_t(sorted[mid]) < v)
      lo = mid + 1;
    else
      hi = mid;
  }
  return lo;
}

// Where each cell's triangles start among the sorted ones (cell ncell: n).
__global__ void cell_start_kernel(const GridShape* grid, const uint32_t* cell_sorted, int32_t n, int32_t* cell_start) {
  const int64_t c = int64_t(blockIdx.x) * blockDim.x + threadIdx.x;
  if (c > grid->nx * grid->ny) return;
  cell_start[c] = lower_bound(cell_sorted, n, c);
}

// Sorted triangle p's candidates, as the CPU's loop visits them: the later
// triangles of its cell, then the four forward neighbours' (any order
// serves: the candidates are sorted by key afterwards). Counted, or written
// from out.
template <bool kWrite>
__global__ void pair_walk_kernel(const GridShape* grid, const uint32_t* cell_sorted, const int32_t* sorted,
                                 const int32_t* cell_start, const int32_t* surface, const int32_t* tri,
                                 const int32_t* body, const double* bx0, const double* by0, const double* bx1,
                                 const double* by1, int32_t n, int32_t* counts, const int32_t* offsets,
                                 uint64_t* out) {
  const int32_t p = blockIdx.x * blockDim.x + threadIdx.x;
  if (p >= n) return;
  const GridShape g = *grid;
  const int32_t i = sorted[p];
  const int64_t c = cell_sorted[p];
  const double bi[4] = {bx0[i], by0[i], bx1[i], by1[i]};
  const int32_t ti = surface[i];
  int32_t k = 0;
  uint64_t* slot = kWrite ? out + offsets[p] : nullptr;
  auto test = [&](int32_t q) {
    const int32_t j = sorted[q];
    const double bj[4] = {bx0[j], by0[j], bx1[j], by1[j]};
    const int32_t tj = surface[j];
    if (!candidate_pair(bi, bj, ti, tj, tri, body)) return;
    if (kWrite) slot[k] = ti < tj ? friction_pair_key(ti, tj) : friction_pair_key(tj, ti);
    ++k;
  };
  for (int32_t q = p + 1; q < cell_start[c + 1]; ++q) test(q);
  int64_t nb[4][2];
  forward_neighbours(c % g.nx, c / g.nx, nb);
  for (int d = 0; d < 4; ++d) {
    if (nb[d][0] < 0 || nb[d][0] >= g.nx || nb[d][1] >= g.ny) continue;
    const int64_t cn = nb[d][1] * g.nx + nb[d][0];
    for (int32_t q = cell_start[cn]; q < cell_start[cn + 1]; ++q) test(q);
  }
  if (!kWrite) counts[p] = k;
}

// The candidates' six nodes (the contactor's, then the target's), keys, and
// each entry 6 c + k with its node, for the sort by node.
__global__ void layout_kernel(const uint64_t* keys, int32_t n, const int32_t* tri, int32_t* node, uint64_t* key,
                              uint32_t* entry_node, int32_t* entry_id) {
  const int32_t c = blockIdx.x * blockDim.x + threadIdx.x;
  if (c >= n) return;
  const uint64_t kk = keys[c];
  const int32_t a = int32_t(kk >> 32), b = int32_t(kk & 0xffffffffu);
  key[c] = kk;  // friction_pair_key(a, b)
  for (int k = 0; k < 3; ++k) {
    node[6 * c + k] = tri[3 * int64_t(a) + k];
    node[6 * c + 3 + k] = tri[3 * int64_t(b) + k];
    entry_node[6 * c + k] = uint32_t(node[6 * c + k]);
    entry_node[6 * c + 3 + k] = uint32_t(node[6 * c + 3 + k]);
  }
  for (int k = 0; k < 6; ++k) entry_id[6 * c + k] = 6 * c + k;
}

// Node i's first entry among the entries sorted by node (node n_nodes: all).
__global__ void node_start_kernel(const uint32_t* entry_node_sorted, int32_t n_entries, int32_t n_nodes,
                                  int32_t* start) {
  const int32_t i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i > n_nodes) return;
  start[i] = lower_bound(entry_node_sorted, n_entries, i);
}

}  // namespace

int32_t DeviceBroadPhase::Impl::search(const double* x, const double* y, const LayoutArrays& out, double& skin) {
  const int32_t n = n_surface;
  skin = 0.0;
  if (n < 2) {  // no pairs (BroadPhase::find)
    out.node->resize(0);
    out.key->resize(0);
    out.entry->resize(0);
    out.start->resize(size_t(n_nodes) + 1);
    cuda_check(cudaMemsetAsync(out.start->data(), 0, out.start->size() * sizeof(int32_t), stream), "memset");
    return 0;
  }
  const int nb = blocks(n, kReduceBlock);
  launch_kernel(box_kernel, nb, kReduceBlock, stream, surface.data(), tri.data(), x, y, n, bx0.data(), by0.data(),
                bx1.data(), by1.data(), partial.data(), nb);
  launch_kernel(grid_kernel, 1, kWide, stream, partial.data(), nb, n, skin_fraction, grid.data(), first_bad.data());
  launch_kernel(bin_kernel, blocks(n), kBlock, stream, grid.data(), n, bx0.data(), by0.data(), bx1.data(),
                by1.data(), cell.data(), index.data());
  const int64_t cap = max_cells(n);
  sort_pairs(scratch, cell.data(), cell_sorted.data(), index.data(), sorted.data(), n, bits_below(cap + 1), stream);
  launch_kernel(cell_start_kernel, blocks(cap + 1), kBlock, stream, grid.data(), cell_sorted.data(), n,
                cell_start.data());
  launch_kernel(pair_walk_kernel<false>, blocks(n), kBlock, stream, grid.data(), cell_sorted.data(), sorted.data(),
                cell_start.data(), surface.data(), tri.data(), body.data(), bx0.data(), by0.data(), bx1.data(),
                by1.data(), n, counts.data(), static_cast<const int32_t*>(nullptr), static_cast<uint64_t*>(nullptr));
  exclusive_sum(scratch, counts.data(), offsets.data(), int64_t(n) + 1, stream);  // counts[n] is 0: offsets[n], all
  cuda_check(cudaMemcpyAsync(host_found, offsets.data() + n, sizeof(int32_t), cudaMemcpyDeviceToHost, stream),
             "copy from GPU");
  cuda_check(cudaMemcpyAsync(host_found + 1, first_bad.data(), sizeof(int32_t), cudaMemcpyDeviceToHost, stream),
             "copy from GPU");
  cuda_check(cudaMemcpyAsync(host_grid, grid.data(), sizeof(GridShape), cudaMemcpyDeviceToHost, stream),
             "copy from GPU");
  cuda_check(cudaStreamSynchronize(stream), "GPU broad phase");
  if (host_found[1] >= 0) {
    // the CPU's message; the triangle whose corner is not finite
    const std::vector<int32_t> s = surface.download();
    throw std::runtime_error("contact detection: non-finite node position in triangle " +
                             std::to_string(s[size_t(host_found[1])]));
  }
  const int32_t m = host_found[0];
  skin = host_grid->skin;
  pairs.resize(size_t(m));
  pairs_sorted.resize(size_t(m));
  out.node->resize(6 * size_t(m));
  out.key->resize(size_t(m));
  out.entry->resize(6 * size_t(m));
  out.start->resize(size_t(n_nodes) + 1);
  entry_node.resize(6 * size_t(m));
  entry_id.resize(6 * size_t(m));
  entry_node_sorted.resize(6 * size_t(m));
  if (m > 0) {
    launch_kernel(pair_walk_kernel<true>, blocks(n), kBlock, stream, grid.data(), cell_sorted.data(), sorted.data(),
                  cell_start.data(), surface.data(), tri.data(), body.data(), bx0.data(), by0.data(), bx1.data(),
                  by1.data(), n, static_cast<int32_t*>(nullptr), static_cast<const int32_t*>(offsets.data()),
                  pairs.data());
    sort_keys(scratch, pairs.data(), pairs_sorted.data(), int64_t(m), 32 + bits_below(n_tri), stream);
    launch_kernel(layout_kernel, blocks(m), kBlock, stream, static_cast<const uint64_t*>(pairs_sorted.data()), m,
                  static_cast<const int32_t*>(tri.data()), out.node->data(), out.key->data(), entry_node.data(),
                  entry_id.data());
    sort_pairs(scratch, entry_node.data(), entry_node_sorted.data(), entry_id.data(), out.entry->data(),
               6 * int64_t(m), bits_below(int64_t(n_nodes)), stream);
  }
  launch_kernel(node_start_kernel, blocks(int64_t(n_nodes) + 1), kBlock, stream,
                static_cast<const uint32_t*>(entry_node_sorted.data()), 6 * m, n_nodes, out.start->data());
  cuda_check(cudaGetLastError(), "kernel launch");
  return m;
}

DeviceBroadPhase::DeviceBroadPhase(const Model& m) : impl_(new Impl) {
  Impl& d = *impl_;
  d.stream = new_stream();
  const std::vector<int32_t>& surface = m.surface_triangles();
  d.n_surface = int32_t(surface.size());
  d.n_nodes = int32_t(m.nodes().size());
  d.n_tri = int32_t(m.triangles().size());
  d.skin_fraction = m.contact().skin_fraction();
  if (6 * int64_t(d.n_nodes) > int64_t(INT32_MAX))
    throw std::invalid_argument("GPU broad phase: " + std::to_string(d.n_nodes) + " nodes, more than it holds");
  d.surface.upload(surface);
  d.tri.upload(m.triangles().node);
  d.body.upload(m.triangles().body);
  const size_t n = surface.size();
  for (auto* a : {&d.bx0, &d.by0, &d.bx1, &d.by1}) a->resize(n);
  d.partial.resize(size_t(n_extremes) * std::max(1, blocks(int64_t(n), kReduceBlock)));
  d.grid.resize(1);
  for (auto* a : {&d.cell, &d.cell_sorted}) a->resize(n);
  for (auto* a : {&d.index, &d.sorted}) a->resize(n);
  d.cell_start.resize(size_t(max_cells(int64_t(n))) + 1);
  d.counts.resize(n + 1);
  d.offsets.resize(n + 1);
  d.first_bad.resize(1);
  cuda_check(cudaMemset(d.counts.data(), 0, d.counts.size() * sizeof(int32_t)), "memset");  // counts[n] stays 0
  cuda_check(cudaMallocHost(&d.host_found, 2 * sizeof(int32_t)), "cudaMallocHost");
  cuda_check(cudaMallocHost(&d.host_grid, sizeof(GridShape)), "cudaMallocHost");
}

DeviceBroadPhase::~DeviceBroadPhase() {
  Impl& d = *impl_;
  if (d.host_found) cudaFreeHost(d.host_found);
  if (d.host_grid) cudaFreeHost(d.host_grid);
  if (d.stream) cudaStreamDestroy(d.stream);
}

// The model's positions on the GPU for a search on its own (the whole step
// searches at its own), the legacy stream's copies done before the search's
// stream reads them.
void DeviceBroadPhase::Impl::upload_positions(const Model& m, DeviceArray<double>& x, DeviceArray<double>& y) {
  const Nodes& N = m.nodes();
  if (int32_t(N.size()) != n_nodes) throw std::invalid_argument("GPU broad phase: the model's nodes changed");
  x.upload(N.x);
  y.upload(N.y);
  cuda_check(cudaDeviceSynchronize(), "GPU uploads");
}

double DeviceBroadPhase::seconds_per_search(const Model& m, int repeats) {
  if (repeats < 1) throw std::invalid_argument("repeats must be at least 1");
  Impl& d = *impl_;
  DeviceArray<double> x, y;
  d.upload_positions(m, x, y);
  DeviceArray<int32_t> node, start, entry;
  DeviceArray<uint64_t> key;
  double skin = 0.0;
  const LayoutArrays out{&node, &key, &start, &entry};
  d.search(x.data(), y.data(), out, skin);  // sizes the outputs
  cuda_check(cudaStreamSynchronize(d.stream), "GPU broad phase");
  double seconds = 0.0;
  {
    Stopwatch sw(seconds);
    for (int k = 0; k < repeats; ++k) d.search(x.data(), y.data(), out, skin);
    cuda_check(cudaStreamSynchronize(d.stream), "GPU broad phase");
  }
  return seconds / repeats;
}

SearchedLayout DeviceBroadPhase::search(const Model& m) {
  Impl& d = *impl_;
  DeviceArray<double> x, y;
  d.upload_positions(m, x, y);
  DeviceArray<int32_t> node, start, entry;
  DeviceArray<uint64_t> key;
  SearchedLayout out;
  d.search(x.data(), y.data(), LayoutArrays{&node, &key, &start, &entry}, out.skin);
  cuda_check(cudaStreamSynchronize(d.stream), "GPU broad phase");
  out.node = node.download();
  out.key = key.download();
  out.start = start.download();
  out.entry = entry.download();
  return out;
}

}  // namespace engine
