// The central-difference update of a step on the GPU (docs/gpu.md): the
// kernel of model/update_kernel.hpp per node, and the ledger's sums in a
// fixed order. A plain C++ header (no CUDA types); in a build without CUDA
// every call says so.
#pragma once
#include <memory>
#include <vector>

namespace engine {

class Model;

struct NodeUpdateFields {
  std::vector<double> x, y, vx, vy;
  // The step's sums (model/step_sums.hpp, NodeWork's order): kinetic2_new,
  // kinetic2_old, viscous, local_damping, contact, friction, cohesive,
  // gravity, buoyancy, drag, boundary, elastic_new, elastic_old.
  std::vector<double> sums;
};

class DeviceNodeUpdate {
 public:
  // Copies the model's node state and the forces of its last evaluation.
  explicit DeviceNodeUpdate(const Model& model);
  ~DeviceNodeUpdate();
  DeviceNodeUpdate(const DeviceNodeUpdate&) = delete;
  DeviceNodeUpdate& operator=(const DeviceNodeUpdate&) = delete;

  void run();  // one update (asynchronous; `fields` waits for it)
  double time_per_run(int repeats);  // [s], device events (the update repeated in place)
  NodeUpdateFields fields();

 private:
  friend class DeviceStep;  // the whole step runs the stage on its state (cuda/device_step.cu)
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace engine
