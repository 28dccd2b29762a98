// The mesh model as the freeze bonds see it: what they read every step, and
// the topology stage's operations a split calls. model/model.hpp's Model is
// the host; through this interface bonds/ needs nothing of model/ (the model
// includes the bonds, not the other way round), and the writes are open to
// FreezeBonds alone.
#pragma once
#include <cstdint>
#include <vector>

#include "common/mesh_arrays.hpp"
#include "contact/contact.hpp"

namespace engine {

class FreezeBonds;

class BondHost {
 public:
  // --- read (every step) ---
  virtual const Nodes& nodes() const = 0;
  virtual const Triangles& triangles() const = 0;
  // Node -> triangle corners, in the fixed order of every per-node sum.
  virtual const NodeGather& gather() const = 0;
  virtual int32_t n_bodies() const = 0;
  // Some triangle of `body` has a corner at `node`.
  virtual bool node_touches_body(int32_t node, int32_t body) const = 0;
  virtual int threads() const = 0;  // 0: OpenMP default
  virtual int64_t step_count() const = 0;
  virtual double time() const = 0;
  virtual double dt() const = 0;
  // The contact's mu (eq 6's compressive branch by default) and penalty (the crack closure).
  virtual const ContactParams& contact_params() const = 0;

  // Relative difference below which masses are the same: the round-off of
  // lumped thirds summed per side in another order (m+ + m- = m unscaled).
  static constexpr double kSameMass = 1e-12;

 protected:
  ~BondHost() = default;

  // --- the bonds' writes: cohesive and crack-closure forces, node splitting ---
  friend class FreezeBonds;
  virtual Nodes& bond_nodes() = 0;
  // Gather list, masses, constraints after a topology edit (and before the
  // bonds are checked against the mesh).
  virtual void prepare_topology() = 0;
  // A new node at `node`'s place and velocity takes over the corners of
  // `body`'s triangles there; returns its id.
  virtual int32_t split_off(int32_t node, int32_t body) = 0;
  // One node's sum of this step's corner forces, gravity and drag.
  virtual void regather_node(int32_t node) = 0;
  // The momentum of every node a split changed the mass of (model.hpp).
  virtual int32_t keep_momentum_through_split(const std::vector<double>& m_before,
                                              const std::vector<int32_t>& split_parent) = 0;
};

}  // namespace engine
