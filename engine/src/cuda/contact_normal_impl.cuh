// The normal contact stage's GPU state (cuda/contact_normal.cu), where the whole
// step (cuda/device_step.cu) can reach it.
#pragma once
#include "cuda/contact_normal.hpp"
#include "cuda/device_array.cuh"

namespace engine {

// Friction's per-candidate pair arrays (cuda/friction_impl.cuh), which the
// pair kernel also writes, as friction's own pair kernel would, where the
// whole step shares the candidates between the two (nc nullptr: not written).
struct FrictionPairOut {
  double* nc = nullptr;
  double* nt = nullptr;
  double* nx = nullptr;
  double* ny = nullptr;
  double* fn = nullptr;
};

struct DeviceContactNormal::Impl {
  int32_t n_nodes = 0;
  int64_t n_pairs = 0;
  double penalty = 0.0;
  DeviceArray<double> x, y, fx, fy, pair_energy, f_con_x, f_con_y, total;
  DeviceArray<int32_t> node, start, entry, touching;
  DeviceArray<uint8_t> hit;
  FrictionPairOut friction_pairs;
  // the launch sums the pairs' energy (total) and counts the touching ones;
  // the whole step sums the energy with the step's other sums (SumJobs)
  bool pair_sums = true;
  cudaStream_t stream = nullptr;
  const int32_t* halt = nullptr;  // the whole step's batch (cuda/halt.cuh); none on its own

  // the stage's launches on `stream` (asynchronous)
  void launch();
  // the per-candidate arrays sized for n candidates (n_pairs n); the layout's
  // arrays (node, start, entry) are the caller's to fill (the making's upload,
  // or the whole step's GPU search, cuda/device_step.cu)
  void size_pairs(size_t n);
};

}  // namespace engine
