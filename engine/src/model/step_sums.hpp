// The sums one step takes over the nodes, each thread over its own block and
// then added in thread order: the result depends on the thread count only
// through that fixed order, so a run is bit-reproducible at a fixed count.
#pragma once

namespace engine {

// Midpoint-rule powers use the mean velocity of the step (v^{n-1/2} +
// v^{n+1/2})/2; the kinetic sums are sum m v² (twice the kinetic energy).
struct StepSums {
  double elastic = 0.0;        // element strain energy at t [J/m] (force pass)
  double kinetic2_new = 0.0;   // sum m v² at n+1/2
  double kinetic2_old = 0.0;   // sum m v² at n-1/2
  double viscous = 0.0;        // power of the viscous element forces
  double contact = 0.0;        // of the contact forces
  double friction = 0.0;       // of the friction forces
  double cohesive = 0.0;       // of the cohesive forces
  double gravity = 0.0;        // of the weight (physical mass)
  double buoyancy = 0.0;
  double drag = 0.0;           // of the drag forces
  double boundary = 0.0;       // of the boundary reactions
  double elastic_new = 0.0;    // elastic force . v^{n+1/2}
  double elastic_old = 0.0;    // elastic force . v^{n-1/2}
  double local_damping = 0.0;  // of the local (Cundall) damping forces
  double sleep_changes = 0.0;  // nodes whose sleep state changed

  StepSums& operator+=(const StepSums& o) {
    elastic += o.elastic;
    kinetic2_new += o.kinetic2_new;
    kinetic2_old += o.kinetic2_old;
    viscous += o.viscous;
    contact += o.contact;
    friction += o.friction;
    cohesive += o.cohesive;
    gravity += o.gravity;
    buoyancy += o.buoyancy;
    drag += o.drag;
    boundary += o.boundary;
    elastic_new += o.elastic_new;
    elastic_old += o.elastic_old;
    local_damping += o.local_damping;
    sleep_changes += o.sleep_changes;
    return *this;
  }
};

// One thread's sums on cache lines of their own (no false sharing).
struct alignas(128) ThreadSums {
  StepSums s;
};

}  // namespace engine
