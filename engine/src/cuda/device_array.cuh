// A typed array in GPU memory (cudaMalloc'd blocks, kept for reuse by
// cuda/device_memory.hpp; never managed memory), and
// the check every CUDA call goes through: a failed call stops with what
// failed, in words, instead of a later wrong number.
#pragma once
#include <cuda_runtime.h>

#include <cstddef>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "cuda/device_memory.hpp"

namespace engine {

inline void cuda_check(cudaError_t e, const char* what) {
  if (e != cudaSuccess)
    throw std::runtime_error(std::string("GPU: ") + what + ": " + cudaGetErrorString(e));
}

template <typename T>
class DeviceArray {
 public:
  DeviceArray() = default;
  explicit DeviceArray(size_t n) { resize(n); }
  ~DeviceArray() { release(); }
  DeviceArray(const DeviceArray&) = delete;
  DeviceArray& operator=(const DeviceArray&) = delete;

  void resize(size_t n) {
    if (n == n_) return;
    release();
    if (n) p_ = static_cast<T*>(device_take(n * sizeof(T)));
    n_ = n;
  }
  void upload(const std::vector<T>& h) {
    resize(h.size());
    if (n_) cuda_check(cudaMemcpy(p_, h.data(), n_ * sizeof(T), cudaMemcpyHostToDevice), "copy to GPU");
  }
  void upload(const T* h, size_t n) {
    resize(n);
    if (n_) cuda_check(cudaMemcpy(p_, h, n_ * sizeof(T), cudaMemcpyHostToDevice), "copy to GPU");
  }
  std::vector<T> download() const {
    std::vector<T> h(n_);
    if (n_) cuda_check(cudaMemcpy(h.data(), p_, n_ * sizeof(T), cudaMemcpyDeviceToHost), "copy from GPU");
    return h;
  }
  // Exchanges the two arrays' memory (a double buffer's turn, no copy).
  void swap(DeviceArray& o) noexcept {
    std::swap(p_, o.p_);
    std::swap(n_, o.n_);
    std::swap(owner_, o.owner_);
  }
  // This array becomes a view of `owner`'s memory (its own is freed): two
  // stages that read and write one quantity share it instead of copying it.
  // The owner must outlive the view, which never frees it.
  void alias(DeviceArray& owner) {
    release();
    p_ = owner.p_;
    n_ = owner.n_;
    owner_ = false;
  }
  T* data() { return p_; }
  const T* data() const { return p_; }
  size_t size() const { return n_; }

 private:
  void release() {
    if (p_ && owner_) device_give(p_);
    p_ = nullptr;
    n_ = 0;
    owner_ = true;
  }
  T* p_ = nullptr;
  size_t n_ = 0;
  bool owner_ = true;  // false: a view of another array's memory (alias)
};

}  // namespace engine
