// The node update's GPU state (cuda/node_update.cu), where the whole step
// (cuda/device_step.cu) can reach it.
#pragma once
#include "cuda/device_array.cuh"
#include "cuda/node_update.hpp"
#include "loads/boundary_kernel.hpp"

namespace engine {

// What the whole step (cuda/device_step.cu) tests of each node right after
// its update, in the update's launch instead of launches of their own: a
// node of a surface triangle moved past the skin since the candidate list
// was built (ContactSolver::list_still_valid's test), and, in the steps whose
// argument row says so, a node moved past half the contact reach since the
// contact step was bound (Model::guard_contact_reach's). Null: not tested.
struct UpdateTests {
  const uint8_t* on_surface = nullptr;  // per node: a node of a surface triangle
  const double* list_x = nullptr;       // where the list was built
  const double* list_y = nullptr;
  double skin = 0.0;
  int32_t* moved = nullptr;             // set to 1 by any such node
  const int64_t* reach_now = nullptr;   // the step's row: tested in this step
  const double* reach_x = nullptr;      // where the contact step was bound
  const double* reach_y = nullptr;
  double reach_half = 0.0;
  int32_t* reach_moved = nullptr;       // set to 1 by any such node
};

// The whole step's boundary conditions at the step's midpoint, applied to
// each node right before its update in the update's launch
// (prescribe_component, Model::apply_boundary_conditions' per-node function):
// x[i] (y[i]) the column of node i's x (y) component in the step's prescribed
// values, -1 where it is free. Null x: none.
struct UpdateBoundary {
  const int32_t* x = nullptr;
  const int32_t* y = nullptr;
  const double* values = nullptr;  // the step's row (GPU memory)
  double inv_dt = 0.0;
  BoundaryComponent cx{}, cy{};
};

struct DeviceNodeUpdate::Impl {
  int32_t n = 0;
  double dt = 0.0, g = 0.0, alpha = 0.0;
  DeviceArray<double> x, y, vx, vy, mass, mass_phys, f_x, f_y, f_pre_x, f_pre_y, f_int_x, f_int_y, f_visc_x,
      f_visc_y, f_con_x, f_con_y, f_coh_x, f_coh_y, f_buoy_y, drag_k, r_x, r_y, v_bc_x, v_bc_y, partial, sums;
  DeviceArray<uint8_t> constrained;
  cudaStream_t stream = nullptr;
  const int32_t* halt = nullptr;  // the whole step's batch (cuda/halt.cuh); none on its own

  int n_blocks() const;  // of the update kernel

  // the update and its sums on `stream` (asynchronous), with the whole
  // step's boundary conditions before each node's update and its tests of
  // the updated nodes
  // (term_sums false: the terms' sums are left to the caller, partial and
  // n_blocks(), as the whole step sums them with its other sums)
  void launch(const UpdateTests& tests = UpdateTests{}, const UpdateBoundary& boundary = UpdateBoundary{},
              bool term_sums = true);
};

}  // namespace engine
