// The cohesive forces of a step on the GPU (docs/gpu.md): the kernel of
// bonds/cohesive_pair_kernel.hpp per opened pair (eqs 8-12), each node's sum
// of its pairs' forces in the CPU's order (pairs ascending), and the energy
// terms summed in a fixed tree. A plain C++ header (no CUDA types); in a
// build without CUDA every call says so.
#pragma once
#include <cstdint>
#include <memory>
#include <vector>

namespace engine {

class Model;

struct CohesiveForceFields {
  std::vector<double> f_coh_x, f_coh_y;  // per node [N/m]
  std::vector<double> fpx, fpy;          // per opened pair (FreezeBonds::open_pairs order): on its + node
  std::vector<double> delta_m;           // per opened pair, after the step
  std::vector<int8_t> failed, mode;      // per opened pair: failed in the step, and how (FailureMode)
  double work = 0.0, stored = 0.0, dissipation = 0.0;  // summed over the pairs
};

class DeviceCohesiveForces {
 public:
  // Copies the model's node state and forces (of its last evaluation) and
  // its opened pairs' history.
  explicit DeviceCohesiveForces(const Model& model);
  ~DeviceCohesiveForces();
  DeviceCohesiveForces(const DeviceCohesiveForces&) = delete;
  DeviceCohesiveForces& operator=(const DeviceCohesiveForces&) = delete;

  void run();
  double time_per_run(int repeats);
  CohesiveForceFields fields();
  int32_t open_pairs() const;

 private:
  friend class DeviceStep;  // the whole step runs the stage on its state (cuda/device_step.cu)
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace engine
