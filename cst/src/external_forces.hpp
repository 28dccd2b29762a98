// Gravity, buoyancy and linear water drag (MODEL.md 3.4).
//
// Buoyancy: each triangle is clipped at the water line y = y_w; the
// submerged part gets rho_w g A_sub upward at its centroid, shared by the
// three corners with the barycentric coordinates of that centroid, so both
// the force and its moment are exact for partially submerged triangles.
//
// Drag: f_i = -c_w v_i sum_e (m_i,e / M_body) (A_sub,e / A_e): the node's mass
// share of its body, scaled per triangle by the submerged fraction. A fully
// submerged body translating rigidly at v feels exactly -c_w v (c_w in Pa s =
// N s/m per m width); a dry body feels none. The drag uses the velocity at
// t - dt/2 (explicit; stable for dt < 2 rho A_body / c_w).
#pragma once
#include <cstdint>
#include <vector>

#include "mesh_arrays.hpp"

namespace cst {

struct ExternalParams {
  bool gravity = true;
  double g = 9.81;         // [m/s²], acts in -y
  bool buoyancy = false;
  bool drag = false;
  double rho_w = 1010.0;   // water density [kg/m³]
  double y_w = 0.0;        // water line [m]
  double c_w = 2.5e4;      // linear drag constant [Pa s]
  bool water() const { return buoyancy || drag; }
};

// Submerged area and centroid of a triangle below y_w.
struct Submerged {
  double area = 0.0, cx = 0.0, cy = 0.0;
};
Submerged submerged_part(double ax, double ay, double bx, double by, double cx, double cy, double y_w);

// Per triangle in [begin, end): buoyancy per corner (f_buoy_corner) and the
// drag coefficient of each corner (drag_k_tri). Returns the submerged area.
double water_forces_on_triangles(const Nodes& nodes, Triangles& tris, const ExternalParams& p,
                                 const std::vector<double>& body_area0, int32_t begin, int32_t end);

}  // namespace cst
