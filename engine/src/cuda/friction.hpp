// Coulomb friction of a step on the GPU (docs/gpu.md), over the candidate
// list as the whole step will run it: which candidates touch, where and how
// hard (the pair kernel of contact/potential_contact_kernel.hpp); the touching
// pairs coloured as contact/friction_order.hpp colours them, in parallel rounds;
// the projected Gauss-Seidel sweeps of contact/friction.cpp colour by colour,
// a lane per pair of a colour in one block, with the per-pair physics of contact/friction_kernel.hpp; then each
// node's sum of its pairs' friction in the CPU's order. A plain C++ header (no
// CUDA types); in a build without CUDA every call says so.
#pragma once
#include <cstdint>
#include <memory>
#include <vector>

namespace engine {

class Model;

struct FrictionFields {
  std::vector<double> f_x, f_y;  // every force of the step, friction included [N/m]
  std::vector<double> lambda;    // tangential force per touching pair [N/m], the CPU's pair order
  double power = 0.0;            // friction's dissipation rate [W/m]
  std::vector<int32_t> colour;   // the sweeps' colour per touching pair, coloured on the GPU
  int32_t colours = 0;
  int32_t rounds = 0;            // the colouring's parallel rounds
  int32_t colourings = 0;        // colourings made by the runs so far (a run whose touching pairs are the
                                 // last colouring's keeps it)
  int32_t local_nodes = 0;       // the touching pairs' nodes the sweeps kept in shared memory (-1: none)
};

class DeviceFriction {
 public:
  // Copies the model's node state, the forces its last evaluation assembled
  // before friction (f_pre), the candidate list of its last contact pass and
  // the friction warm start it holds now (after Model::evaluate: the one that
  // evaluation started from).
  // The warm start as the model holds it (the keys of its last step's
  // touching pairs, sorted), or laid out per candidate (the candidates' keys,
  // NaN where one did not touch: how the whole step keeps it between steps).
  enum class WarmStart { model_keys, per_candidate };
  explicit DeviceFriction(const Model& model, WarmStart warm_start = WarmStart::model_keys);
  ~DeviceFriction();
  DeviceFriction(const DeviceFriction&) = delete;
  DeviceFriction& operator=(const DeviceFriction&) = delete;

  void run();                        // asynchronous; `fields` waits for it
  double time_per_run(int repeats);  // [s], device events
  FrictionFields fields();
  int32_t candidates() const;
  // How many of a touching pair's earlier neighbours on each of its nodes the
  // colouring keeps in a list (0 to the most, kEarlier in friction.cu); a node
  // with more is walked each round. Fewer only to test that walk: the colours
  // are the same.
  void set_earlier_list(int32_t n);
  // How many of the touching pairs' nodes the sweeps may keep in shared
  // memory (0 to the most, most_shared_nodes in friction.cu: kSharedNodes or
  // what this GPU's blocks hold; more: they read the nodes' arrays). Fewer
  // only to test that path: the forces are the same.
  void set_shared_nodes(int32_t n);

 private:
  friend class DeviceStep;  // the whole step runs the stage on its state (cuda/device_step.cu)
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace engine
