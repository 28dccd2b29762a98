// The body-force stage of a step on the GPU (docs/gpu.md): elements (1),
// buoyancy and drag (6), and the node gather, the kernels of
// element/cst_kernel.hpp, loads/water_kernel.hpp, loads/drag_kernel.hpp and
// model/gather_kernel.hpp launched per triangle, body and node. A plain C++
// header (no CUDA types), so the bindings compile without nvcc; in a build
// without CUDA every call says so.
#pragma once
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace engine {

class Model;

// Whether this build has the GPU backend, and the GPU it sees ("" if none).
bool cuda_built();
// whether it was built against the CPU emulation of the CUDA runtime (no toolkit; cuda/emulation/)
bool cuda_emulated();
std::string cuda_device_name();

// The stage's outputs, copied back for a comparison with the CPU's.
struct BodyForceFields {
  std::vector<double> f_int_x, f_int_y, f_visc_x, f_visc_y, f_buoy_y, drag_k, f_x, f_y;
  std::vector<double> stress, energy;  // per triangle
  double elastic_energy = 0.0;         // sum of energy, in a fixed order
  int32_t first_inverted = -1;
};

class DeviceBodyForces {
 public:
  // Copies the model's mesh, materials and node state to the GPU.
  explicit DeviceBodyForces(const Model& model);
  ~DeviceBodyForces();
  DeviceBodyForces(const DeviceBodyForces&) = delete;
  DeviceBodyForces& operator=(const DeviceBodyForces&) = delete;

  // Positions and velocities of the model now.
  void upload_state(const Model& model);
  // One evaluation of the stage (asynchronous; `fields` waits for it).
  void run();
  // Mean wall time of one evaluation over `repeats` [s], from device events
  // (the launches captured once in a CUDA graph).
  double time_per_run(int repeats);
  // Mean wall time of each stage over `repeats` evaluations launched one by
  // one [s]: quadratic drag, triangles (elements, water, energy partials),
  // node gather, energy sum.
  std::vector<double> stage_times(int repeats);
  BodyForceFields fields();

 private:
  friend class DeviceStep;  // the whole step runs the stage on its state (cuda/device_step.cu)
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace engine
