// Stable time step of the explicit central-difference scheme.
//
// Elements: the largest eigenfrequency of the lumped-mass system is bounded by
// the largest element eigenfrequency (Irons' theorem); for a CST with lumped
// mass m/3 per node, w_e² = (3/rho) lambda_max(D^½ B B^T D^½) (plane strain D),
// about 1.8 c_d/h_min (c_d = sqrt((lambda+2 mu)/rho) the dilatational wave
// speed, h_min the smallest altitude). Strain-rate damping at ratio
// xi = w_e tau/2 lowers the limit to (2/w_e)(sqrt(1+xi²) - xi).
// Contact: a surface node of mass m against the penalty s (stiffness ~ s per
// m of overlap depth, N/m per m), two such nodes: w² = 2 s/m.
// Drag: explicit linear drag on a node is stable for dt < 2 m_i/k_i =
// 2 rho A_body/c_w.
// The stable step is SAFETY times the smallest of these limits.
#pragma once
#include "contact/contact.hpp"
#include <cstdint>
#include <string>
#include <vector>

#include "loads/external_forces.hpp"
#include "element/material.hpp"
#include "common/mesh_arrays.hpp"

namespace engine {

constexpr double kTimeStepSafety = 0.9;

struct StableStep {
  double dt = 0.0;  // kTimeStepSafety * min(limits)
  double dt_element = 0.0;
  int32_t element = -1;     // governing triangle
  double altitude = 0.0;    // its smallest altitude [m]
  double wave_speed = 0.0;  // its dilatational wave speed [m/s]
  double damping_ratio = 0.0;
  double dt_contact = 0.0;  // infinite when contact cannot happen
  int32_t contact_node = -1;
  double contact_mass = 0.0;
  double dt_drag = 0.0;
  int32_t drag_body = -1;
  // Mass scaling (EngineParameters::mass_scaling_dt): the target step (0: off), the
  // inertial mass added over the physical mass [kg/m], its fraction of the
  // total physical mass, and how many nodes carry added mass.
  double mass_scaling_dt = 0.0;
  double added_mass = 0.0;
  double added_mass_fraction = 0.0;
  int32_t scaled_nodes = 0;
  std::string governing() const;  // "element", "contact" or "drag"
  std::string describe(const std::vector<int32_t>& tri_body) const;
};

// Undamped critical step 2/w_e of one triangle with reference corners a, b, c.
double element_critical_dt(double ax, double ay, double bx, double by, double cx, double cy,
                           const ElementMaterial& m);

// Damped limit of an element with undamped limit dt0 (w = 2/dt0) and damping
// time tau (strain-rate damping and viscosity, xi = w tau/2), its corner
// masses mass_ratio times the physical: inertial mass r times the physical
// lowers every eigenfrequency by at least sqrt(r), and (2/w)(sqrt(1+xi²) - xi)
// falls with w, so the limit is evaluated there: sqrt(r dt0² + tau²) - tau.
// Where damping dominates it grows as r, not sqrt(r).
double damped_dt(double dt0, double tau, double mass_ratio = 1.0);

// Its inverse in the mass: the ratio r with damped_dt(dt0, tau, r) = need,
// r = need (need + 2 tau)/dt0² (selective mass scaling, Model::scale_masses).
double mass_ratio_for(double dt0, double tau, double need);

// Undamped critical step of triangle t (reference corners, physical masses).
double element_undamped_dt(const Nodes& nodes, const Triangles& tris,
                           const std::vector<ElementMaterial>& mat, int32_t t);

// Element limits use the inertial masses: damped_dt of each triangle's
// undamped limit dt0[t] (element_undamped_dt) with r the smallest corner
// ratio mass/mass_phys.
StableStep stable_time_step(const Nodes& nodes, const Triangles& tris,
                            const std::vector<ElementMaterial>& mat, const std::vector<double>& dt0,
                            bool contact_possible, const ContactStableStep& contact,
                            const ExternalParams& ext,
                            const std::vector<double>& body_area0);

}  // namespace engine
