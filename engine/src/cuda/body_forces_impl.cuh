// The body-force stage's GPU state (cuda/body_forces.cu), where the whole
// step (cuda/device_step.cu) can reach it: the stage's arrays are the step's
// mesh and node state.
#pragma once
#include "cuda/body_forces.hpp"
#include "cuda/device_array.cuh"
#include "element/material.hpp"
#include "loads/external_forces.hpp"

namespace engine {

struct DeviceBodyForces::Impl {
  int32_t n_nodes = 0, n_tri = 0, n_bodies = 0;
  bool damping = false, water = false, quadratic = false;
  ExternalParams ext;
  // mesh
  DeviceArray<int32_t> node, body, start, slot, body_start, body_corner, surf_start, surf_node;
  DeviceArray<double> binv00, binv01, binv10, binv11, area0, body_area0, body_weight, mass_phys;
  DeviceArray<ElementMaterial> material;
  // state and outputs
  DeviceArray<double> x, y, vx, vy, c_b, term_x, term_y, stress, corner_load, energy;
  DeviceArray<double> f_int_x, f_int_y, f_visc_x, f_visc_y, f_buoy_y, drag_k, f_x, f_y, f_coh_x, f_coh_y;
  DeviceArray<double> total, partial;
  // events after each stage when the stages are timed apart (kernel_times)
  cudaEvent_t stage_end[4] = {nullptr, nullptr, nullptr, nullptr};
  bool timing_stages = false;

  void mark(int k) {
    if (timing_stages) cuda_check(cudaEventRecord(stage_end[k], stream), "event");
  }
  DeviceArray<int32_t> inverted;
  // the launch sets `inverted` to none first; the whole step does that only
  // where a step starts afresh (reset_flags, cuda/device_step.cu: a set flag
  // halts the batch): a launch fewer a step
  bool reset_inverted = true;
  // the launch sums the strain energy (total) from the triangles' blocks'
  // partials; the whole step sums it with the step's other sums (SumJobs)
  bool sum_energy = true;
  cudaStream_t stream = nullptr;
  const int32_t* halt = nullptr;  // the whole step's batch (cuda/halt.cuh); none on its own
  cudaGraphExec_t graph = nullptr;

  // the stage's launches on `stream` (asynchronous)
  void launch();
};

}  // namespace engine
