// The node update's GPU state (cuda/node_update.cu), where the whole step
// (cuda/device_step.cu) can reach it.
#pragma once
#include "cuda/device_array.cuh"
#include "cuda/node_update.hpp"

namespace engine {

struct DeviceNodeUpdate::Impl {
  int32_t n = 0;
  double dt = 0.0, g = 0.0, alpha = 0.0;
  DeviceArray<double> x, y, vx, vy, mass, mass_phys, f_x, f_y, f_pre_x, f_pre_y, f_int_x, f_int_y, f_visc_x,
      f_visc_y, f_con_x, f_con_y, f_coh_x, f_coh_y, f_buoy_y, drag_k, r_x, r_y, v_bc_x, v_bc_y, partial, sums;
  DeviceArray<uint8_t> constrained;
  cudaStream_t stream = nullptr;
  const int32_t* halt = nullptr;  // the whole step's batch (cuda/halt.cuh); none on its own

  int n_blocks() const;  // of the update kernel

  // the update and its sums on `stream` (asynchronous)
  void launch();
};

}  // namespace engine
