// Whole time steps on the GPU (docs/gpu.md), as far as they are built: the
// step of Model::step for a model without the sleeping far field. The stages are the backend's (cuda/body_forces.cu,
// contact_normal.cu, bond_check.cu, cohesive_forces.cu, friction.cu,
// node_update.cu) on one stream, chained on the GPU, with the boundary
// conditions and the force assembly of the CPU's per-node functions
// (loads/boundary_kernel.hpp, model/assemble_kernel.hpp). A step whose bond
// check finds a point at the criterion is taken by the model itself
// (cuda/device_step.cu); where the candidate list is due, the GPU searches
// it (cuda/broad_phase.cu) and the contact stages take it in place, the
// GPU's steps going on. Steps run
// in batches, read back in one copy: each step's ledger sums, energies and
// flags (an element inverted, the list must be rebuilt, a node past reach/2); the
// host books the ledger and guards the run; the state stays on the GPU until
// `download`.
// A plain C++ header (no CUDA types); in a build without CUDA every call
// says so.
#pragma once
#include <cstdint>
#include <memory>
#include <vector>

#include "model/energy.hpp"

namespace engine {

class Model;

class DeviceStep {
 public:
  // Prepares the model as Model::step does (its dt checked against the
  // stable step) and copies its mesh, state, boundary conditions, clock,
  // ledger, its bonds' state, to the GPU. Throws std::invalid_argument
  // naming what the GPU step does not run yet: the sleeping far field. The
  // model must outlive this: it takes the steps the GPU does not.
  explicit DeviceStep(Model& model);
  ~DeviceStep();
  DeviceStep(const DeviceStep&) = delete;
  DeviceStep& operator=(const DeviceStep&) = delete;

  // n steps. Throws InstabilityError (model.hpp) when the energies stop
  // being finite or an element inverts; the state is then that step's (on the
  // energy alarm, the ledger is that step's and the state its batch's last).
  void step(int64_t n);
  // The state on the GPU into `model` (the one it was made from): positions,
  // velocities, clock, ledger, friction warm start and the bonds' state (the
  // opened pairs' history, failures, screening flags and accounts); the
  // model, or this on more steps, continues from there. Also the last
  // step's boundary reactions and the elements' stresses, these at the
  // state the steps ended in (on the CPU, at the one its last step started
  // from).
  void download(Model& model);
  // Sum of the boundary reactions on these nodes from the last step [N/m],
  // as Model::reaction sums them.
  void reaction(const std::vector<int32_t>& nodes, double& rx, double& ry);

  double time() const;
  int64_t step_count() const;
  // Steps the model took itself (bond points split there) since this was made.
  int64_t host_steps() const;
  // Times the candidate list was rebuilt (the model's broad phase at the
  // GPU's positions, put into the contact stages in place) since this was
  // made, and the wall time of those rebuilds [s] (copies included).
  int64_t list_rebuilds() const;
  double list_seconds() const;
  // Times the stages were made again from the model since this was made
  // (after each host step, a pair's full failure, a re-bound contact step):
  // each copies the mesh and state to the GPU.
  int64_t remakes() const;
  // Wall time [s] since this was made: in the host steps (the state to the
  // model, its step, its next list after a split), and in making the stages
  // from the model (the first making included: allocations and copies).
  double host_step_seconds() const;
  // A batch's CUDA graph captured again (after a list rebuild or a remake):
  // instantiated afresh, or put into the executable graph in place where its
  // launches are the same (cudaGraphExecUpdate).
  int64_t graph_instantiations() const;
  int64_t graph_updates() const;
  // Times friction coloured its touching pairs since this was made: a step
  // whose touching pairs are those of the colouring before keeps it
  // (cuda/friction.cu), so fewer than the steps with contact.
  int64_t colourings() const;
  double make_seconds() const;
  const EnergyLedger& energy() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace engine
