// The normal contact pass of a step on the GPU (docs/gpu.md): the pair kernel
// of contact/potential_contact_kernel.hpp per candidate pair of the CPU's
// broad phase, and each node's sum over its pairs in the CPU's order
// (touching pairs by (contactor, target), a pair's six nodes in turn). A plain
// C++ header (no CUDA types); in a build without CUDA every call says so.
#pragma once
#include <cstdint>
#include <memory>
#include <vector>

namespace engine {

class Model;

struct ContactNormalFields {
  std::vector<double> f_con_x, f_con_y;  // normal contact force per node [N/m]
  double energy = 0.0;                   // stored energy of the touching pairs [J/m]
  int32_t touching = 0;                  // touching pairs
};

class DeviceContactNormal {
 public:
  // Copies the model's positions, triangles and the candidate list of its
  // last contact pass (Model::evaluate or step builds it).
  explicit DeviceContactNormal(const Model& model);
  ~DeviceContactNormal();
  DeviceContactNormal(const DeviceContactNormal&) = delete;
  DeviceContactNormal& operator=(const DeviceContactNormal&) = delete;

  void run();
  double time_per_run(int repeats);  // [s], device events
  ContactNormalFields fields();
  int64_t candidates() const;

 private:
  friend class DeviceStep;  // the whole step runs the stage on its state (cuda/device_step.cu)
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace engine
