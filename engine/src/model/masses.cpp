// Lumped nodal masses and selective mass scaling.
#include "common/input_errors.hpp"
#include "model/model.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include "model/time_step.hpp"

namespace engine {

namespace {

// The margin absorbs the round-off of squaring and taking the root again, so
// the stable step is not below the target.
constexpr double kMassMargin = 1.0 + 1e-12;

// Inertial mass [kg/m] a node of contact stiffness k needs for its contact
// limit sqrt(2 m / k) to reach `need` (= target step / safety).
inline double contact_mass_for(double k, double need) { return 0.5 * k * need * need * kMassMargin; }

}  // namespace

// Each triangle's undamped limit, from its reference corners and its body's
// material alone: a corner is only ever re-pointed to a node at its own
// reference place (a bond split; set_triangle_node refuses any other), so the
// limits are kept through splits (a split step took them for the whole mesh,
// the paper mesh's 86,000 triangles, twice) and taken again when a material changes.
void Model::compute_element_limits() {
  auto same = [](const ElementMaterial& a, const ElementMaterial& b) {
    return a.lambda == b.lambda && a.shear_modulus == b.shear_modulus && a.rho == b.rho;
  };
  bool current = element_dt0_.size() == size_t(tris_.size()) && element_dt0_mat_.size() == elem_mat_.size();
  for (size_t b = 0; current && b < elem_mat_.size(); ++b) current = same(element_dt0_mat_[b], elem_mat_[b]);
  if (current) return;
  element_dt0_.resize(size_t(tris_.size()));
  for (int32_t t = 0; t < tris_.size(); ++t) element_dt0_[t] = element_undamped_dt(nodes_, tris_, elem_mat_, t);
  element_dt0_mat_ = elem_mat_;
}

void Model::compute_masses() {
  for (int32_t b = 0; b < n_bodies(); ++b)
    if (!materials_[b].set) {
      for (int32_t body : tris_.body)
        if (body == b)
          bad("material of body " + std::to_string(b) + " is not set (E, nu, rho, damping, viscosity)");
    }
  elem_mat_.resize(materials_.size());
  any_damping_ = false;
  for (size_t b = 0; b < materials_.size(); ++b) {
    elem_mat_[b] = ElementMaterial::from(materials_[b]);
    any_damping_ = any_damping_ || materials_[b].damping > 0.0 || materials_[b].viscosity > 0.0;
  }
  compute_element_limits();
  body_area0_.assign(materials_.size(), 0.0);
  std::fill(nodes_.mass.begin(), nodes_.mass.end(), 0.0);
  for (int32_t t = 0; t < tris_.size(); ++t) body_area0_[tris_.body[t]] += tris_.area0[t];
  // Lumped: a third of each triangle's mass per corner, summed in gather order.
  for (int32_t i = 0; i < nodes_.size(); ++i) {
    double m = 0.0;
    for (int32_t k = gather_.start[i]; k < gather_.start[i + 1]; ++k) {
      const int32_t t = gather_.slot[k] / 3;
      m += materials_[tris_.body[t]].rho * tris_.area0[t] / 3.0;
    }
    nodes_.mass[i] = m;
  }
  nodes_.mass_phys = nodes_.mass;
  scale_masses();
  if (!any_damping_) {
    for (size_t c = 0; c < tris_.corner_load.size(); c += CornerLoad::stride)
      tris_.corner_load[c + CornerLoad::visc_x] = tris_.corner_load[c + CornerLoad::visc_y] = 0.0;
    std::fill(nodes_.f_visc_x.begin(), nodes_.f_visc_x.end(), 0.0);
    std::fill(nodes_.f_visc_y.begin(), nodes_.f_visc_y.end(), 0.0);
  }
}

// Selective mass scaling. Element limit: with corner masses r m_phys a
// triangle's damped limit is sqrt(r dt0² + tau²) - tau (time_step.hpp; dt0
// its undamped limit, tau its damping time), so each corner of a triangle with
// limit dt_e < need = dt_target/safety needs r >= need (need + 2 tau)/dt0².
// In a tiny element the viscosity dominates (dt_e ~ dt0²/2 tau) and this is
// far less mass than (need/dt_e)². Contact limit sqrt(2 m / k): m >= k (dt_target/safety)²/2,
// with k the node's stiffness from the contact module (node splitting keeps
// it: k is per body). Both carry kMassMargin (above).
void Model::scale_masses() {
  added_mass_ = 0.0;
  scaled_nodes_ = 0;
  total_mass_phys_ = 0.0;
  for (double m : nodes_.mass_phys) total_mass_phys_ += m;
  if (!(params_.mass_scaling_dt > 0.0)) return;
  const double need = params_.mass_scaling_dt / kTimeStepSafety;
  std::vector<double>& M = nodes_.mass;
  const std::vector<double>& Mp = nodes_.mass_phys;
  for (int32_t t = 0; t < tris_.size(); ++t) {
    const double tau = elem_mat_[tris_.body[t]].tau_eff();
    if (damped_dt(element_dt0_[t], tau) >= need) continue;
    const double r = mass_ratio_for(element_dt0_[t], tau, need) * kMassMargin;
    for (int c = 0; c < 3; ++c) {
      const int32_t i = tris_.node[3 * t + c];
      M[i] = std::max(M[i], Mp[i] * r);
    }
  }
  if (contact_possible_) {
    std::vector<double> k;
    // in the reference configuration: a resumed run gets the masses of the run it continues
    contact_critical_dt(reference_contact_stiffness(), nodes_.mass.data(), &k);
    for (int32_t i = 0; i < nodes_.size(); ++i)
      if (k[i] > 0.0) M[i] = std::max(M[i], contact_mass_for(k[i], need));
  }
  for (int32_t i = 0; i < nodes_.size(); ++i) M[i] = std::max(M[i], nodes_.mass_floor[i]);
  for (int32_t i = 0; i < nodes_.size(); ++i)
    if (M[i] > Mp[i]) {
      added_mass_ += M[i] - Mp[i];
      ++scaled_nodes_;
    }
}

// The contact reach guard found nodes within reach of stiffer boundaries than
// when the step was bound (guard_contact_reach). With mass scaling on, those
// nodes get the mass the current step needs, as the reference scaling would
// have given them there: their momentum is kept (v scaled by m_old/m_new), and
// the kinetic energy this takes out, 1/2 m_old v^2 (1 - m_old/m_new), is booked
// as damping so the ledger still closes (with the half-step shift of
// rescale_velocity). The new mass is the node's floor from
// then on. Nodes with prescribed motion keep their velocity (the boundary
// condition sets it; 1/2 (m_old - m_new) v^2 is booked). Returns the number
// of nodes raised.
int32_t Model::raise_contact_masses(const ContactStiffness& now) {
  std::vector<double> k;
  contact_critical_dt(now, nodes_.mass.data(), &k);
  const double need = dt_ / kTimeStepSafety;
  Nodes& N = nodes_;
  double lost = 0.0;
  int32_t raised = 0;
  for (int32_t i = 0; i < N.size(); ++i) {
    if (!(k[i] > 0.0)) continue;
    const double m_new = contact_mass_for(k[i], need);
    const double m_old = N.mass[i];
    if (m_new <= m_old) continue;
    const double v2 = N.vx[i] * N.vx[i] + N.vy[i] * N.vy[i];
    if (!N.constrained[i]) {
      const double r = m_old / m_new;
      lost += 0.5 * m_old * v2 * (1.0 - r) + rescale_velocity(i, r);
    } else {
      lost += 0.5 * (m_old - m_new) * v2;  // its velocity is prescribed: only the books change
    }
    if (m_old <= N.mass_phys[i]) ++scaled_nodes_;
    added_mass_ += m_new - m_old;
    N.mass[i] = N.mass_floor[i] = m_new;
    ++raised;
  }
  energy_.damping += lost;
  raised_nodes_ += raised;
  report_added_mass();
  return raised;
}

// A split node's velocity is shared by its pieces (split_off copies it), so
// the momentum of a node and of what split off it is (sum of new masses) v:
// scaled by m_before / (sum of new masses) it is the node's momentum before.
// A mass that changed by round-off only (the lumped thirds summed per side in
// another order) changes nothing: without mass scaling m+ + m- = m.
int32_t Model::keep_momentum_through_split(const std::vector<double>& m_before,
                                           const std::vector<int32_t>& split_parent) {
  Nodes& N = nodes_;
  const size_t n_before = m_before.size();
  if (n_before + split_parent.size() != size_t(N.size()))
    bad("keep_momentum_through_split: " + std::to_string(n_before) + " nodes before and " +
        std::to_string(split_parent.size()) + " split off do not make the " + std::to_string(N.size()) +
        " nodes there are");
  std::vector<double> m_group(N.mass.begin(), N.mass.begin() + n_before);
  for (size_t j = 0; j < split_parent.size(); ++j) m_group[split_parent[j]] += N.mass[n_before + j];
  std::vector<double> r(n_before, 1.0);
  int32_t changed = 0;
  for (size_t i = 0; i < n_before; ++i)
    if (std::fabs(m_group[i] - m_before[i]) > kSameMass * m_before[i]) {
      r[i] = m_before[i] / m_group[i];
      ++changed;
    }
  if (!changed) return 0;
  // 1/2 m v^2 booked before, less what the pieces carry after (a node with
  // prescribed motion keeps its velocity: only the books change)
  double lost = 0.0;
  const auto rescale = [&](int32_t node, double factor) {
    if (!N.constrained[node]) lost += rescale_velocity(node, factor);
    lost -= 0.5 * N.mass[node] * (N.vx[node] * N.vx[node] + N.vy[node] * N.vy[node]);
  };
  for (size_t j = 0; j < split_parent.size(); ++j)
    if (r[split_parent[j]] != 1.0) rescale(int32_t(n_before + j), r[split_parent[j]]);
  for (size_t i = 0; i < n_before; ++i)
    if (r[i] != 1.0) {
      lost += 0.5 * m_before[i] * (N.vx[i] * N.vx[i] + N.vy[i] * N.vy[i]);
      rescale(int32_t(i), r[i]);
    }
  energy_.damping += lost;
  return changed;
}

// The ledger's works run from the half-step position x - dt v/2 that a
// node's velocity v implies (integrator.cpp), and its elastic energy is taken
// there: a velocity changed outside the update (a mass change that keeps the
// momentum, a node put to sleep) moves that point by -dt (v' - v)/2, which
// changes the elastic energy by the elastic force's work dt f_el.(v' - v)/2
// without a source. Returns that, for the books to take as damping (with f_el
// at x, not at the half step: O(dt) of it, round-off).
double Model::rescale_velocity(int32_t i, double factor) {
  Nodes& N = nodes_;
  const double dvx = (factor - 1.0) * N.vx[i], dvy = (factor - 1.0) * N.vy[i];
  N.vx[i] += dvx;
  N.vy[i] += dvy;
  return -0.5 * dt_ * ((N.f_int_x[i] - N.f_visc_x[i]) * dvx + (N.f_int_y[i] - N.f_visc_y[i]) * dvy);
}

void Model::report_added_mass() {
  stable_.mass_scaling_dt = params_.mass_scaling_dt;
  stable_.added_mass = added_mass_;
  stable_.added_mass_fraction = total_mass_phys_ > 0.0 ? added_mass_ / total_mass_phys_ : 0.0;
  stable_.scaled_nodes = scaled_nodes_;
}

int32_t Model::reset_contact_masses() {
  Nodes& N = nodes_;
  const std::vector<double> m_old = N.mass;
  std::fill(N.mass_floor.begin(), N.mass_floor.end(), 0.0);
  prepared_ = false;
  stable_current_ = false;
  prepare();
  // velocities stay: at rest the change is tiny, and it is booked
  double before = 0.0, after = 0.0;
  for (int32_t i = 0; i < N.size(); ++i) {
    const double v2 = N.vx[i] * N.vx[i] + N.vy[i] * N.vy[i];
    before += 0.5 * m_old[i] * v2;
    after += 0.5 * N.mass[i] * v2;
  }
  energy_.damping += before - after;
  if (!(contact_possible_ && std::isfinite(params_.contact_reach) && params_.mass_scaling_dt > 0.0)) return 0;
  reach_x_ = N.x;  // the reach guard measures moves from here
  reach_y_ = N.y;
  // only the nodes that need more than they have
  return raise_contact_masses(contact_stiffness(params_.contact, contact_input(), params_.contact_reach));
}

void Model::set_reach_origin(const std::vector<double>& x, const std::vector<double>& y) {
  // nodes split off since the last bound have none yet: they start from their
  // reference places when the stable step is next taken (as in the run saved)
  if (x.size() != y.size() || int64_t(x.size()) > nodes_.size())
    bad("reach origin must have as many x as y, at most one per node (" + std::to_string(nodes_.size()) +
        "), got " + std::to_string(x.size()) + " and " + std::to_string(y.size()));
  reach_x_ = x;
  reach_y_ = y;
}

void Model::set_mass_floor(const std::vector<double>& floor) {
  if (int64_t(floor.size()) != nodes_.size())
    bad("mass floor must have one entry per node (" + std::to_string(nodes_.size()) + ")");
  for (double f : floor)
    if (!(f >= 0.0 && std::isfinite(f))) bad("mass floor of a node must be finite and >= 0 kg/m");
  nodes_.mass_floor = floor;
  prepared_ = false;  // masses change
  stable_current_ = false;
}

}  // namespace engine
