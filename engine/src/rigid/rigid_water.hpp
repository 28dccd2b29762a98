// Buoyancy and water drag on rigid blocks (the discrete-only comparison
// model, docs/model.md §6): the FEM-DEM laws of loads/external_forces.hpp
// integrated exactly over a rigid polygon, so both models float, rise and
// drag alike.
//
// A block is a convex or concave simple polygon (counter-clockwise corners
// relative to its centroid c, in its body frame), at position c, angle theta,
// velocity V and angular velocity omega. Its part below the water line y_w
// has area A_s, centroid c_s and polar second moment I_s about c. Per metre
// of width:
//   buoyancy  F_b = rho_w g A_s (upward, at c_s: torque (c_s - c) x F_b);
//   drag      the FEM-DEM's -c_b v over the block's submerged area share,
//             integrated for rigid motion v(r) = V + omega z x r:
//             F_d = -(c_b / A) (A_s V + omega z x (A_s (c_s - c))),
//             T_d = -(c_b / A) ((A_s (c_s - c)) x V + omega I_s);
//   c_b       c_w (linear), or 1/2 rho_w C_d |V| L (quadratic; L the
//             block's width across V), or 0 (none).
// Weight is not included (the host applies gravity).
#pragma once
#include <cstdint>

#include "loads/external_forces.hpp"

namespace engine {

struct RigidBlocks {
  int32_t n = 0;
  const int32_t* offset = nullptr;  // n + 1: corners of block b are [offset[b], offset[b+1])
  const double* vx = nullptr;       // body-frame corner coordinates relative to the centroid [m]
  const double* vy = nullptr;
  const double* area = nullptr;     // each block's area [m²] (of its polygon)
  const double* cx = nullptr;       // centroid position [m]
  const double* cy = nullptr;
  const double* theta = nullptr;    // rotation angle about z [rad]
  const double* ux = nullptr;       // centroid velocity [m/s]
  const double* uy = nullptr;
  const double* omega = nullptr;    // angular velocity [rad/s]
};

// Forces (fx, fy) [N/m] and torques tz [N m/m] of water on every block.
// Blocks are independent: `threads` share them, and each block's sums are
// taken in its own corner order whatever the thread count.
void rigid_water_forces(const RigidBlocks& b, const ExternalParams& p, double* fx, double* fy,
                        double* tz, int threads);

// The submerged part of one polygon (world corners px, py; n of them,
// counter-clockwise) below y_w: area, first moments about (ox, oy) and polar
// second moment about (ox, oy).
struct SubmergedMoments {
  double area = 0.0, sx = 0.0, sy = 0.0, polar = 0.0;
};
SubmergedMoments submerged_moments(const double* px, const double* py, int32_t n, double y_w,
                                   double ox, double oy);

}  // namespace engine
