// Pair kernel of the potential contact force method (Munjiza; paper section
// 2.1, eqs 1-3; docs/model.md §3.2): the penalty force between one contactor and one
// target triangle of different bodies.
//
// Potential. In each triangle phi = 3 * min(lambda_0, lambda_1, lambda_2)
// (lambda: area coordinates): 1 at the centroid, 0 on the edges, linear on the
// three sub-triangles (centroid, edge). On the sub-triangle that touches edge
// i (the edge opposite node i) phi = 3 lambda_i.
//
// Stored energy. The pair stores
//     E = s * integral over the overlap (phi_c + phi_t) dOmega          (*)
// and the nodal forces are its exact gradient, f_a = -dE/dx_a, so a
// frictionless collision conserves (kinetic + elastic + contact) energy up to
// the time integration error. Derivation, for the target potential term
// E_t = s int_{c∩t} phi_t:
//  - moving the contactor nodes with the affine field u = sum_j N^c_j u_j moves
//    only the part of the overlap boundary that lies on the contactor, and phi_t
//    vanishes on the rest (the target edges), so
//        dE_t/du_j = s int_{c∩t} div(phi_t N^c_j) = s int (N^c_j grad phi_t + phi_t grad N^c_j);
//  - moving the target nodes with w = sum_k N^t_k w_k convects phi_t
//    (d phi_t/dt = -w . grad phi_t at a fixed point) while the contactor region
//    stays put, and phi_t is continuous and zero outside the target, so
//        dE_t/dw_k = -s int_{c∩t} N^t_k grad phi_t.
//  The contactor potential term E_c is the same with the roles swapped.
// The resultant on the contactor is -s int grad phi_t + s int grad phi_c,
// i.e. eq 3 for both directions (contactor in the target's potential and
// target in the contactor's), and the target gets exactly the opposite. As the
// gradient of a translation- and rotation-invariant energy, the six nodal
// forces have zero resultant and zero moment (linear and angular momentum are
// conserved). Because grad phi is constant on each sub-triangle and N, phi are
// linear there, every integral is exact from the area and centroid of the
// overlap polygon clipped to each sub-triangle (no quadrature error).
#pragma once

namespace engine {

struct PairContact {
  // Forces [N per m width] on the contactor nodes (0..2) and target nodes (3..5),
  // in the node order given to potential_contact_pair.
  double fx[6];
  double fy[6];
  double energy;  // E of (*) [J per m width]
  double area;    // overlap area [m^2]
  double px, py;  // overlap centroid: the contact point used by friction
  double nc[3];   // contactor shape functions at (px, py)
  double nt[3];   // target shape functions at (px, py)
};

}  // namespace engine

// potential_contact_pair(xc, yc, xt, yt, s, out): returns false (and leaves
// `out` unspecified) when the triangles do not overlap with positive area.
// Either orientation of the node order is accepted. s: penalty [Pa per m width].
#include "contact/potential_contact_kernel.hpp"
