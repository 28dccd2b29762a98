// Per-body isotropic linear elastic material with strain-rate damping
// (docs/model.md §3.1). St Venant-Kirchhoff: the linear law between Green-Lagrange
// strain and second Piola-Kirchhoff stress, objective under any rotation.
#pragma once

namespace engine {

struct Material {
  double E = 0.0;        // Young's modulus [Pa]
  double nu = 0.3;       // Poisson's ratio [-] (the paper gives none: 0.3)
  double rho = 0.0;      // density [kg/m³]
  // Strain-rate damping time [s]: viscous stress S_v = damping * C : dE/dt
  // (Kelvin-Voigt with the elastic tensor C), so a mode of angular frequency
  // w is damped at ratio xi = w * damping / 2. Default 0 (no damping).
  double damping = 0.0;
  // Viscosity of the block material [Pa s] (Munjiza-type FEM-DEM codes):
  // viscous stress eta x rate of Green strain (~ eta D, D the rate of
  // deformation), on top of the damping above. A mode of angular frequency w
  // whose stiffness is the modulus M is damped at ratio w eta / (2 M).
  double viscosity = 0.0;
  bool set = false;
};

// Plane-strain constants the element kernel uses.
struct ElementMaterial {
  double lambda = 0.0;  // Lamé lambda [Pa]
  double shear_modulus = 0.0;  // Lamé mu [Pa] (mu is the friction coefficient elsewhere)
  double tau = 0.0;     // damping time [s]
  double eta = 0.0;     // viscosity [Pa s]
  double rho = 0.0;
  // Damping time that bounds the damping ratio of every element mode from
  // above: the viscosity damps a shear mode (stiffness 2 mu) the most.
  double tau_eff() const { return tau + (shear_modulus > 0.0 ? eta / (2.0 * shear_modulus) : 0.0); }

  static ElementMaterial from(const Material& m) {
    ElementMaterial e;
    e.lambda = m.E * m.nu / ((1.0 + m.nu) * (1.0 - 2.0 * m.nu));
    e.shear_modulus = m.E / (2.0 * (1.0 + m.nu));
    e.tau = m.damping;
    e.eta = m.viscosity;
    e.rho = m.rho;
    return e;
  }
};

}  // namespace engine
