// Per-body isotropic linear elastic material with strain-rate damping
// (MODEL.md 3.1). St Venant-Kirchhoff: the linear law between Green-Lagrange
// strain and second Piola-Kirchhoff stress, objective under any rotation.
#pragma once

namespace cst {

struct Material {
  double E = 0.0;        // Young's modulus [Pa]
  double nu = 0.3;       // Poisson's ratio [-] (the paper gives none: 0.3)
  double rho = 0.0;      // density [kg/m³]
  // Strain-rate damping time [s]: viscous stress S_v = damping * C : dE/dt
  // (Kelvin-Voigt with the elastic tensor C), so a mode of angular frequency
  // w is damped at ratio xi = w * damping / 2. Default 0 (no damping).
  double damping = 0.0;
  bool set = false;
};

// Plane-strain constants the element kernel uses.
struct ElementMaterial {
  double lambda = 0.0;  // Lamé lambda [Pa]
  double mu = 0.0;      // shear modulus [Pa]
  double tau = 0.0;     // damping time [s]
  double rho = 0.0;

  static ElementMaterial from(const Material& m) {
    ElementMaterial e;
    e.lambda = m.E * m.nu / ((1.0 + m.nu) * (1.0 - 2.0 * m.nu));
    e.mu = m.E / (2.0 * (1.0 + m.nu));
    e.tau = m.damping;
    e.rho = m.rho;
    return e;
  }
};

}  // namespace cst
