// The bond check of a step on the GPU (docs/gpu.md): the kernel of
// bonds/bond_check_kernel.hpp per intact bond point (eqs 5-7), giving the
// split plan the host's topology stage carries out. A plain C++ header (no
// CUDA types); in a build without CUDA every call says so.
#pragma once
#include <cstdint>
#include <memory>
#include <vector>

namespace engine {

class Model;

struct BondCheckFields {
  std::vector<double> ratio;   // per bond point (NaN where it has split)
  std::vector<double> tn, tt;  // per pair [Pa]
  std::vector<int32_t> plan;   // the points at the criterion, ascending
};

class DeviceBondCheck {
 public:
  // Copies the model's positions, stresses (of its last evaluation), gather
  // lists and bonds.
  explicit DeviceBondCheck(const Model& model);
  ~DeviceBondCheck();
  DeviceBondCheck(const DeviceBondCheck&) = delete;
  DeviceBondCheck& operator=(const DeviceBondCheck&) = delete;

  void run();  // every intact point, no screening
  double time_per_run(int repeats);
  BondCheckFields fields();

 private:
  friend class DeviceStep;  // the whole step runs the stage on its state (cuda/device_step.cu)
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace engine
