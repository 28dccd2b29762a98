// The bond check's GPU state (cuda/bond_check.cu), where the whole step
// (cuda/device_step.cu) can reach it.
#pragma once
#include "bonds/bond_check_kernel.hpp"
#include "cuda/bond_check.hpp"
#include "cuda/device_array.cuh"

namespace engine {

struct DeviceBondCheck::Impl {
  int32_t n_points = 0, n_pairs = 0, n_intact = 0;
  double mu = 0.0;
  // FreezeBonds::check's pre-screening (BondParams)
  int32_t screen_interval = 1;
  double screen_fraction = 0.5;
  DeviceArray<double> x, y, stress, area0, sigma_cr, tau_cr, beta, d0x, d0y, n0x, n0y, tn, tt, ratio;
  DeviceArray<int32_t> start, slot, point_node, first_pair, n_pairs_of, frame_p, frame_q, intact;
  // the screened check's state: each point's flag before the step and after
  // it (a double buffer: a step whose check finds a split is not the GPU's,
  // so its flags are not kept), a point at the criterion, points evaluated
  DeviceArray<int8_t> near, near_next;
  DeviceArray<int32_t> split;
  DeviceArray<unsigned long long> evaluated;
  cudaStream_t stream = nullptr;
  const int32_t* halt = nullptr;  // the whole step's batch (cuda/halt.cuh); none on its own

  // The check's arrays at the given positions and triangle stresses.
  BondCheckArrays arrays(const double* at_x, const double* at_y, const double* at_stress);
  // the check of every intact point at the stage's own state (asynchronous)
  void launch();
  // FreezeBonds::check as a committed step of step number *step (GPU
  // memory: a batch's step reads its own) runs it, at these positions and
  // stresses: a point is evaluated when its flag is set or in its turn of
  // the screening; near_next gets the flags after the check, split 1 when a
  // point reaches eq 5, evaluated the count. The caller zeroes split and
  // evaluated first (asynchronous).
  void launch_screened(const double* at_x, const double* at_y, const double* at_stress, const int64_t* step);
};

}  // namespace engine
