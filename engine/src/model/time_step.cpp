#include "model/time_step.hpp"

#include <cmath>
#include <limits>
#include <sstream>

namespace engine {

namespace {

// Largest eigenvalue of a symmetric 3x3 matrix (trigonometric method).
double max_eigenvalue_sym3(const double a[3][3]) {
  const double p1 = a[0][1] * a[0][1] + a[0][2] * a[0][2] + a[1][2] * a[1][2];
  const double q = (a[0][0] + a[1][1] + a[2][2]) / 3.0;
  const double p2 = (a[0][0] - q) * (a[0][0] - q) + (a[1][1] - q) * (a[1][1] - q) +
                    (a[2][2] - q) * (a[2][2] - q) + 2.0 * p1;
  if (p2 <= 0.0) return q;
  const double p = std::sqrt(p2 / 6.0);
  double b[3][3];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) b[i][j] = (a[i][j] - (i == j ? q : 0.0)) / p;
  const double det = b[0][0] * (b[1][1] * b[2][2] - b[1][2] * b[2][1]) -
                     b[0][1] * (b[1][0] * b[2][2] - b[1][2] * b[2][0]) +
                     b[0][2] * (b[1][0] * b[2][1] - b[1][1] * b[2][0]);
  const double r = std::fmax(-1.0, std::fmin(1.0, 0.5 * det));
  return q + 2.0 * p * std::cos(std::acos(r) / 3.0);
}

constexpr double kInf = std::numeric_limits<double>::infinity();

}  // namespace

double element_critical_dt(double ax, double ay, double bx, double by, double cx, double cy,
                           const ElementMaterial& m) {
  const double px[3] = {ax, bx, cx}, py[3] = {ay, by, cy};
  const double two_a = (bx - ax) * (cy - ay) - (cx - ax) * (by - ay);
  double sbb = 0.0, scc = 0.0, sbc = 0.0;
  for (int i = 0; i < 3; ++i) {
    const int j = (i + 1) % 3, k = (i + 2) % 3;
    const double b = (py[j] - py[k]) / two_a, c = (px[k] - px[j]) / two_a;
    sbb += b * b;
    scc += c * c;
    sbc += b * c;
  }
  // BBt = B B^T in Voigt form (xx, yy, engineering xy).
  const double BBt[3][3] = {{sbb, 0.0, sbc}, {0.0, scc, sbc}, {sbc, sbc, sbb + scc}};
  // Eigenbasis of the plane-strain D: (1,1,0)/√2, (1,-1,0)/√2, (0,0,1).
  const double r2 = 1.0 / std::sqrt(2.0);
  const double Q[3][3] = {{r2, r2, 0.0}, {r2, -r2, 0.0}, {0.0, 0.0, 1.0}};
  const double s[3] = {std::sqrt(2.0 * m.lambda + 2.0 * m.shear_modulus), std::sqrt(2.0 * m.shear_modulus),
                       std::sqrt(m.shear_modulus)};
  double H[3][3];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      double h = 0.0;
      for (int k = 0; k < 3; ++k)
        for (int l = 0; l < 3; ++l) h += Q[k][i] * BBt[k][l] * Q[l][j];
      H[i][j] = s[i] * h * s[j];
    }
  const double w2 = 3.0 * max_eigenvalue_sym3(H) / m.rho;
  return 2.0 / std::sqrt(w2);
}

double element_undamped_dt(const Nodes& nodes, const Triangles& tris,
                           const std::vector<ElementMaterial>& mat, int32_t t) {
  const int32_t a = tris.node[3 * t], b = tris.node[3 * t + 1], c = tris.node[3 * t + 2];
  return element_critical_dt(nodes.x0[a], nodes.y0[a], nodes.x0[b], nodes.y0[b], nodes.x0[c],
                             nodes.y0[c], mat[tris.body[t]]);
}

double damped_dt(double dt0, double tau, double mass_ratio) {
  // sqrt(r dt0² + tau²) - tau, written without the cancellation at large tau
  const double r_dt0_2 = mass_ratio * dt0 * dt0;
  return r_dt0_2 / (std::sqrt(r_dt0_2 + tau * tau) + tau);
}

double mass_ratio_for(double dt0, double tau, double need) {
  return need * (need + 2.0 * tau) / (dt0 * dt0);
}

std::string StableStep::governing() const {
  if (dt_element <= dt_contact && dt_element <= dt_drag) return "element";
  return dt_contact <= dt_drag ? "contact" : "drag";
}

std::string StableStep::describe(const std::vector<int32_t>& tri_body) const {
  std::ostringstream o;
  o.precision(4);
  o << "stable time step " << dt << " s (" << kTimeStepSafety
    << " x the smallest limit, governed by " << governing() << "); element limit " << dt_element
    << " s at triangle " << element;
  if (element >= 0)
    o << " of body " << tri_body[element] << " (smallest altitude " << altitude
      << " m, dilatational wave speed " << wave_speed << " m/s, damping ratio "
      << damping_ratio << ")";
  o << "; contact limit ";
  if (std::isfinite(dt_contact))
    o << dt_contact << " s at surface node " << contact_node << " (mass " << contact_mass
      << " kg/m against the penalty)";
  else
    o << "none (fewer than two bodies)";
  if (std::isfinite(dt_drag)) o << "; drag limit " << dt_drag << " s (body " << drag_body << ")";
  if (mass_scaling_dt > 0.0)
    o << "; mass scaling to " << mass_scaling_dt << " s: " << scaled_nodes << " nodes carry "
      << added_mass << " kg/m of added inertial mass (" << 100.0 * added_mass_fraction
      << " % of the physical mass)";
  return o.str();
}

StableStep stable_time_step(const Nodes& nodes, const Triangles& tris,
                            const std::vector<ElementMaterial>& mat, const std::vector<double>& element_dt0,
                            bool contact_possible, const ContactStableStep& contact,
                            const ExternalParams& ext,
                            const std::vector<double>& body_area0) {
  StableStep s;
  s.dt_element = s.dt_contact = s.dt_drag = kInf;
  for (int32_t t = 0; t < tris.size(); ++t) {
    const int32_t a = tris.node[3 * t], b = tris.node[3 * t + 1], c = tris.node[3 * t + 2];
    const double dt0 = element_dt0[t];
    const double tau = mat[tris.body[t]].tau_eff();
    // Without mass scaling mass == mass_phys and the ratio is exactly 1.
    const double ratio = std::fmin(nodes.mass[a] / nodes.mass_phys[a],
                                   std::fmin(nodes.mass[b] / nodes.mass_phys[b],
                                             nodes.mass[c] / nodes.mass_phys[c]));
    const double dt = damped_dt(dt0, tau, ratio);
    if (dt < s.dt_element) {
      s.dt_element = dt;
      s.element = t;
      s.damping_ratio = tau / dt0;   // xi = w tau/2 with w = 2/dt0
    }
  }
  if (s.element >= 0) {
    const int32_t t = s.element;
    double longest = 0.0;
    for (int i = 0; i < 3; ++i) {
      const int32_t p = tris.node[3 * t + i], q = tris.node[3 * t + (i + 1) % 3];
      longest = std::fmax(longest, std::hypot(nodes.x0[q] - nodes.x0[p], nodes.y0[q] - nodes.y0[p]));
    }
    s.altitude = 2.0 * tris.area0[t] / longest;
    const ElementMaterial& m = mat[tris.body[t]];
    s.wave_speed = std::sqrt((m.lambda + 2.0 * m.shear_modulus) / m.rho);
  }
  if (contact_possible) {
    // The potential contact stiffness of a boundary node is several times the
    // penalty (contact.hpp, contact_critical_dt): ask the contact module.
    s.dt_contact = contact.dt;
    s.contact_node = contact.node;
    s.contact_mass = contact.mass;
  }
  if (ext.drag_on() && ext.drag_model == DragModel::Linear && ext.c_w > 0.0) {
    for (size_t b = 0; b < body_area0.size(); ++b) {
      if (!(body_area0[b] > 0.0)) continue;
      const double dt = 2.0 * mat[b].rho * body_area0[b] / ext.c_w;
      if (dt < s.dt_drag) {
        s.dt_drag = dt;
        s.drag_body = int32_t(b);
      }
    }
  }
  s.dt = kTimeStepSafety * std::fmin(s.dt_element, std::fmin(s.dt_contact, s.dt_drag));
  return s;
}

}  // namespace engine
