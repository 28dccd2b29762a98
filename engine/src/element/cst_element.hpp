// The constant-strain triangle, total Lagrangian (docs/model.md §3.1).
//
// F = Ds Dm^-1 from current and reference edge vectors, Green-Lagrange strain
// E = (F^T F - I)/2, St Venant-Kirchhoff S = lambda tr(E) I + 2 mu E (plane
// strain), strain-rate damping S_v = tau (lambda tr(dE/dt) I + 2 mu dE/dt)
// + eta dE/dt (eta the block viscosity),
// nodal forces from the first Piola-Kirchhoff stress P = F (S + S_v):
// f_corner = -A0 P Dm^-T. A rigid rotation gives F^T F = I, hence zero stress,
// at any angle.
#pragma once
#include <cstdint>
#include <vector>

#include "element/cst_kernel.hpp"
#include "element/material.hpp"
#include "common/mesh_arrays.hpp"

namespace engine {

// Reference shape of one triangle: fills Dm^-1 and the area. Returns the
// signed reference area (<= 0: clockwise or degenerate; caller reports it).
double element_reference(double X0, double Y0, double X1, double Y1, double X2, double Y2,
                         double& b00, double& b01, double& b10, double& b11);

struct ElementSweep {
  double elastic_energy = 0.0;  // sum of A0 W(E) [J/m]
  int32_t inverted = -1;        // first triangle with det F <= 0 in the range
};

// Internal forces, elastic Cauchy stress and strain energy (also kept per
// triangle, Triangles::energy) of triangles [begin, end), or of
// list[begin..end) when a list is given (the awake triangles of a sleeping
// far field), added to the sums already in `out`. Velocities (t - dt/2)
// enter only through the damping stress.
void element_forces(const Nodes& nodes, Triangles& tris, const std::vector<ElementMaterial>& mat,
                    bool damping, int32_t begin, int32_t end, ElementSweep& out,
                    const int32_t* list = nullptr);

// The element pass's arrays of a mesh (element/cst_kernel.hpp).
CstArrays cst_arrays(const Nodes& nodes, Triangles& tris, const std::vector<ElementMaterial>& mat);

// Strain energy of one triangle at the current positions [J/m] (diagnostics).
double element_strain_energy(const Nodes& nodes, const Triangles& tris,
                             const std::vector<ElementMaterial>& mat, int32_t t);

}  // namespace engine
