// Flat node and triangle arrays of the engine (structure of arrays).
//
// Node arrays are std::vectors so that freeze-bond node splitting can append
// nodes; triangle connectivity can be rewritten in place (a corner's node id
// replaced by the split node). After either change Model::rebuild_topology()
// recomputes masses, the node->corner gather list and the surface triangles.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

namespace engine {

struct Nodes {
  std::vector<double> x, y;    // current position [m]
  std::vector<double> x0, y0;  // reference (initial) position [m]
  // Between steps: velocity at t - dt/2 of the next step (central difference).
  std::vector<double> vx, vy;
  // Inertial mass [kg per m width]: the lumped mass, raised at the few nodes
  // that limit the stable step when mass scaling is on (EngineParameters::mass_scaling_dt).
  // Everything dynamic uses it: the update, kinetic energy, boundary
  // reactions, the friction predictor, contact and bond-split masses, the
  // stable step.
  std::vector<double> mass;
  // Physical lumped mass [kg per m width] (a third of each triangle's mass per
  // corner): the weight m g, so that gravity (and with it the draft and the
  // load on the keel) stays physical under mass scaling.
  std::vector<double> mass_phys;
  // Inertial mass a node must keep at least [kg/m] (0: none): raised mid-run
  // when the contact reach guard finds the node within reach of a stiffer
  // boundary (Model::raise_contact_masses); kept through mass recomputation
  // after bond points split, and in checkpoints.
  std::vector<double> mass_floor;

  // Forces of the current step by origin [N/m]; kept apart so that the work
  // of each can be integrated (energy bookkeeping, docs/model.md §4).
  std::vector<double> f_int_x, f_int_y;    // element forces, elastic + viscous
  std::vector<double> f_visc_x, f_visc_y;  // viscous (strain-rate damping) part
  std::vector<double> f_con_x, f_con_y;    // normal contact (potential contact)
  std::vector<double> f_coh_x, f_coh_y;    // cohesive forces of opened freeze bonds
  std::vector<double> f_buoy_y;            // buoyancy (vertical)
  std::vector<double> drag_k;              // drag f = -drag_k v [kg/(m s) per m]
  std::vector<double> f_x, f_y;            // total, friction included
  std::vector<double> f_pre_x, f_pre_y;    // total before friction
  std::vector<double> r_x, r_y;            // force the boundary conditions add
  std::vector<uint8_t> constrained;        // bit 0: x prescribed, bit 1: y
  std::vector<double> v_bc_x, v_bc_y;      // prescribed velocity at t + dt/2
  // Sleeping far field (model/sleeping.hpp): 0 awake, 1 fell asleep at the
  // last update, 2 asleep since an earlier one; how many updates in a row
  // an awake node has been slower than the sleep velocity; and an asleep
  // node's total force at its first frozen update (what it wakes against).
  std::vector<uint8_t> sleep;
  std::vector<int32_t> quiet;
  std::vector<double> f_ref_x, f_ref_y;

  int32_t size() const { return static_cast<int32_t>(x.size()); }
  // Grows (or shrinks) every array; new entries are zero.
  void resize(int32_t n);
  size_t bytes() const;
};

// The fields of a corner's record in Triangles::corner_load.
struct CornerLoad {
  static constexpr int fx = 0, fy = 1;          // element force, elastic + viscous [N/m]
  static constexpr int visc_x = 2, visc_y = 3;  // its viscous part [N/m]
  static constexpr int buoy_y = 4;              // buoyancy [N/m]
  static constexpr int drag_k = 5;              // the corner's share of the drag coefficient [N s/m²]
  static constexpr int stride = 6;
};

struct Triangles {
  std::vector<int32_t> node;  // 3 per triangle, counter-clockwise in the reference
  std::vector<int32_t> body;  // body id per triangle
  // Inverse of the reference edge matrix Dm = [X1-X0, X2-X0] (columns), so that
  // the deformation gradient is F = Ds * Dm^-1 (total Lagrangian).
  std::vector<double> binv00, binv01, binv10, binv11;
  std::vector<double> area0;  // reference area [m²]
  // Elastic Cauchy stress (sxx, syy, sxy) per triangle [Pa], from the last
  // force evaluation; what eq 7 (bond-point traction) area-averages.
  std::vector<double> stress;
  // Per-corner loads of the last evaluation, gathered onto the nodes
  // (deterministic; no scattered writes), one record of CornerLoad::stride
  // doubles per corner slot 3*t+k. Interleaved because the gather reads all of
  // a corner's loads together: one cache line per corner instead of four.
  std::vector<double> corner_load;
  std::vector<double> energy;         // strain energy A0 W(E) of the last evaluation [J/m]

  int32_t size() const { return static_cast<int32_t>(body.size()); }
  void resize(int32_t m);
  size_t bytes() const;
};

// Which triangle corners touch each node (compressed rows, ascending corner
// slot 3*tri+corner), so that nodal forces are gathered in a fixed order.
struct NodeGather {
  std::vector<int32_t> start;  // n_nodes + 1
  std::vector<int32_t> slot;   // 3 * n_tri
  size_t bytes() const {
    return (start.capacity() + slot.capacity()) * sizeof(int32_t);
  }
};

}  // namespace engine
