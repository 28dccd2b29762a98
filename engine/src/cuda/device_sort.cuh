// The GPU broad phase's two whole-array primitives (cuda/broad_phase.cu): a
// stable sort of (key, value) pairs by key and an exclusive prefix sum of
// counts, on a stream, into arrays the caller gives. A CUDA build takes
// them from CUB (the toolkit's; LSD radix sort, stable); the CPU emulation
// runs std::stable_sort and a running sum as the stream's work. Both give
// one result, whatever the order of equal keys' arrival: the sort is stable
// and the sums are of integers.
#pragma once
#include <cuda_runtime.h>

#include <cstdint>

#include "cuda/device_array.cuh"
#include "cuda/launch.cuh"

#ifdef ICERUBBLE_CUDA_EMULATION
#include <algorithm>
#include <numeric>
#include <vector>
#else
#include <cub/device/device_radix_sort.cuh>
#include <cub/device/device_scan.cuh>
#endif

namespace engine {

#ifdef ICERUBBLE_CUDA_EMULATION
namespace emulated {
template <class K, class V>
void sort_pairs(const K* keys_in, K* keys_out, const V* vals_in, V* vals_out, int64_t n) {
  std::vector<int64_t> order(static_cast<size_t>(n));
  std::iota(order.begin(), order.end(), int64_t(0));
  std::stable_sort(order.begin(), order.end(), [&](int64_t a, int64_t b) { return keys_in[a] < keys_in[b]; });
  std::vector<K> k(static_cast<size_t>(n));
  std::vector<V> v(static_cast<size_t>(n));
  for (int64_t i = 0; i < n; ++i) {
    k[size_t(i)] = keys_in[order[size_t(i)]];
    v[size_t(i)] = vals_in[order[size_t(i)]];
  }
  std::copy(k.begin(), k.end(), keys_out);
  std::copy(v.begin(), v.end(), vals_out);
}
inline void exclusive_sum(const int32_t* in, int32_t* out, int64_t n) {
  int32_t s = 0;
  for (int64_t i = 0; i < n; ++i) {
    const int32_t c = in[i];
    out[i] = s;
    s += c;
  }
}
}  // namespace emulated
#endif

// keys_out, vals_out: keys_in, vals_in ordered by key (equal keys in input
// order), the lowest `key_bits` bits of the keys compared (all above zero).
// scratch grows as the CUB call asks.
template <class K, class V>
void sort_pairs(DeviceArray<uint8_t>& scratch, const K* keys_in, K* keys_out, const V* vals_in, V* vals_out,
                int64_t n, int key_bits, cudaStream_t stream) {
  if (n <= 0) return;
#ifdef ICERUBBLE_CUDA_EMULATION
  (void)scratch;
  (void)key_bits;
  cuda_emu::launch(stream, dim3(1), dim3(1),
                   [=] { emulated::sort_pairs(keys_in, keys_out, vals_in, vals_out, n); });
#else
  size_t bytes = 0;
  cuda_check(cub::DeviceRadixSort::SortPairs(nullptr, bytes, keys_in, keys_out, vals_in, vals_out, n, 0, key_bits,
                                             stream),
             "radix sort (scratch size)");
  if (scratch.size() < bytes) scratch.resize(bytes);
  cuda_check(cub::DeviceRadixSort::SortPairs(scratch.data(), bytes, keys_in, keys_out, vals_in, vals_out, n, 0,
                                             key_bits, stream),
             "radix sort");
#endif
}

// keys_out: keys_in ascending, the lowest `key_bits` bits compared.
template <class K>
void sort_keys(DeviceArray<uint8_t>& scratch, const K* keys_in, K* keys_out, int64_t n, int key_bits,
               cudaStream_t stream) {
  if (n <= 0) return;
#ifdef ICERUBBLE_CUDA_EMULATION
  (void)scratch;
  (void)key_bits;
  cuda_emu::launch(stream, dim3(1), dim3(1), [=] {
    std::copy(keys_in, keys_in + n, keys_out);
    std::stable_sort(keys_out, keys_out + n);
  });
#else
  size_t bytes = 0;
  cuda_check(cub::DeviceRadixSort::SortKeys(nullptr, bytes, keys_in, keys_out, n, 0, key_bits, stream),
             "radix sort (scratch size)");
  if (scratch.size() < bytes) scratch.resize(bytes);
  cuda_check(cub::DeviceRadixSort::SortKeys(scratch.data(), bytes, keys_in, keys_out, n, 0, key_bits, stream),
             "radix sort");
#endif
}

// out[i] = in[0] + ... + in[i - 1] (out[0] = 0), n entries.
inline void exclusive_sum(DeviceArray<uint8_t>& scratch, const int32_t* in, int32_t* out, int64_t n,
                          cudaStream_t stream) {
  if (n <= 0) return;
#ifdef ICERUBBLE_CUDA_EMULATION
  (void)scratch;
  cuda_emu::launch(stream, dim3(1), dim3(1), [=] { emulated::exclusive_sum(in, out, n); });
#else
  size_t bytes = 0;
  cuda_check(cub::DeviceScan::ExclusiveSum(nullptr, bytes, in, out, n, stream), "prefix sum (scratch size)");
  if (scratch.size() < bytes) scratch.resize(bytes);
  cuda_check(cub::DeviceScan::ExclusiveSum(scratch.data(), bytes, in, out, n, stream), "prefix sum");
#endif
}

}  // namespace engine
