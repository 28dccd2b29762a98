// Gravity, buoyancy and water drag (docs/model.md §3.4).
//
// Buoyancy: each triangle is clipped at the water line y = y_w; the
// submerged part gets rho_w g A_sub upward at its centroid, shared by the
// three corners with the barycentric coordinates of that centroid, so both
// the force and its moment are exact for partially submerged triangles.
//
// Drag: f_i = -c_b v_i sum_e (m_i,e / M_body) (A_sub,e / A_e): the node's mass
// share of its body's drag constant c_b, scaled per triangle by the submerged
// fraction. A fully submerged body translating rigidly at v feels exactly
// -c_b v; a dry body feels none. The body's constant c_b depends on the model:
//   linear:    c_b = c_w (Pa s = N s/m per m width), the same for every body;
//   quadratic: c_b = 1/2 rho_w C_d |V| L, form drag of a body moving at its
//              mean velocity V with L its width across V, so the body feels
//              -1/2 rho_w C_d |V| V L (per m width);
//   none:      no drag.
// The drag uses the velocity at t - dt/2 (explicit; stable for dt < 2 rho
// A_body / c_b: for quadratic drag that bound is ~1e8 m/s over any block's
// speed at the steps used here, so it does not enter the stable step).
#pragma once
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "common/mesh_arrays.hpp"
#include "loads/water_kernel.hpp"

namespace engine {

enum class DragModel : int { None = 0, Linear = 1, Quadratic = 2 };

// The drag models' names in DragModel's order: the registry's drag_model
// choices (external_forces.cpp holds the two to one set at compile time).
inline constexpr const char* kDragModelNames[] = {"none", "linear", "quadratic"};
DragModel drag_model_named(const std::string& name);  // refuses another name, giving the registry's range
inline const char* drag_model_name(DragModel m) { return kDragModelNames[int(m)]; }

// The water and gravity parameters. No defaults here: they are the
// registry's (icerubble/parameters.py), sent whole with the engine's other
// parameters (model/engine_parameters.hpp); a number not given is NaN.
struct ExternalParams {
  bool gravity = false;
  double g = NAN;          // acts in -y [m/s²]
  bool buoyancy = false;
  bool drag = false;
  double rho_w = NAN;      // [kg/m³]
  double y_w = NAN;        // water line [m]
  double c_w = NAN;        // linear drag constant [Pa s]
  DragModel drag_model = DragModel::None;
  double C_d = NAN;        // form drag coefficient (quadratic model) [-]
  bool drag_on() const { return drag && drag_model != DragModel::None; }
  bool water() const { return buoyancy || drag_on(); }
};

// The check of these against the registry's ranges (where they enter: the
// engine's parameters, the rigid-block model's water forces).
void validate(const ExternalParams& p);

// The water pass's arrays of a mesh (loads/water_kernel.hpp).
WaterArrays water_arrays(const Nodes& nodes, Triangles& tris, const ExternalParams& p,
                         const std::vector<double>& body_area0, const std::vector<double>& body_drag);

// Per triangle in [begin, end): buoyancy per corner and the drag coefficient
// of each corner (Triangles::corner_load) from the bodies' drag
// constants body_drag (N s/m per m width). Returns the submerged area.
double water_forces_on_triangles(const Nodes& nodes, Triangles& tris, const ExternalParams& p,
                                 const std::vector<double>& body_area0,
                                 const std::vector<double>& body_drag, int32_t begin, int32_t end,
                                 const int32_t* list = nullptr);

// Each body's triangles, in the order of the drag's sums (compressed rows by
// body, ascending triangle ids), held as what the sums read: a triangle's
// three corners and its weight area0 / 3 at its place k (the sums stream
// through them instead of looking up the triangle, then its nodes, then
// dividing its area; docs/gpu.md has the time it saved). And
// each body's surface points: the corners of its triangles that have a corner
// on a boundary, each once (the width's extremes lie on the boundary, and a
// set's extremes are the same in any order).
struct BodyTriangleLists {
  std::vector<int32_t> start;                         // n_bodies + 1
  std::vector<int32_t> corner;                        // 3 per place k
  std::vector<double> weight;                         // per place k: area0 / 3
  std::vector<int32_t> surface_start, surface_node;   // n_bodies + 1, the surface points
  // The bodies by descending triangle count (ties by id): threads take the
  // large bodies first, so the paper mesh's two layer halves (~8,800
  // triangles each, against ~200 of a block) no longer come last and hold
  // the other threads back (a body's sum stays one thread's, in its order).
  std::vector<int32_t> largest_first;
  void build(const Triangles& tris, const std::vector<int32_t>& surface, int32_t n_bodies, int32_t n_nodes);
  size_t bytes() const;
};

// Every body's drag constant c_b for the current velocities (see above);
// quadratic drag needs each body's mean velocity (area weighted, from the
// triangles, so shared bond nodes count for both bodies) and its width across
// that velocity (from its surface points: a body's extremes lie on its
// boundary). Bodies are independent: `threads` share them, and every
// body's sums are taken in its ascending triangle order whatever the count.
void body_drag_constants(const Nodes& nodes, const ExternalParams& p,
                         const std::vector<double>& body_area0, std::vector<double>& body_drag,
                         const BodyTriangleLists& lists, int threads);

}  // namespace engine
