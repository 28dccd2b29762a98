// One node's total force before friction (docs/model.md §3: the sum of
// stages (1)-(6)), written once for both backends: Model::assemble_forces
// loops over it, the GPU step launches it per node (cuda/device_step.cu).
#pragma once
#include <cstdint>

#include "common/host_device.hpp"

namespace engine {

struct AssembleArrays {
  double* f_x;  // in: elements, gravity, water; out: the total
  double* f_y;
  const double* f_con_x;  // normal contact
  const double* f_con_y;
  const double* f_coh_x;  // cohesive
  const double* f_coh_y;
  double* f_pre_x;  // the total, kept: friction and the ledger read it
  double* f_pre_y;
};

ICERUBBLE_HD void assemble_node(const AssembleArrays& a, int32_t i) {
  a.f_x[i] += a.f_con_x[i] + a.f_coh_x[i];
  a.f_y[i] += a.f_con_y[i] + a.f_coh_y[i];
  a.f_pre_x[i] = a.f_x[i];
  a.f_pre_y[i] = a.f_y[i];
}

}  // namespace engine
