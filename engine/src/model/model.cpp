#include "common/input_errors.hpp"
#include "model/model.hpp"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <tuple>

namespace engine {

namespace {

constexpr int kPartialStride = 16;  // doubles per thread: 2 cache lines, no false sharing
constexpr int kMaxThreads = 256;
constexpr double kGrowthFactor = 10.0;
// Below this many triangles a step is a few tens of microseconds of work and
// waking a second thread (twice per step) costs more than it saves.
constexpr int32_t kMinParallelTriangles = 2048;

void require_finite_positive(const char* name, double v, const char* unit) {
  if (!(v > 0.0) || !std::isfinite(v))
    bad(std::string(name) + " must be > 0 " + unit + " and finite (got " + num(v) + ")");
}

void require_finite_nonnegative(const char* name, double v, const char* unit) {
  if (!(v >= 0.0) || !std::isfinite(v))
    bad(std::string(name) + " must be >= 0 " + unit + " and finite (got " + num(v) + ")");
}

// Thread t of nt takes [begin, end) of n items: contiguous static blocks.
inline void block(int64_t n, int t, int nt, int32_t& begin, int32_t& end) {
  begin = int32_t(n * t / nt);
  end = int32_t(n * (t + 1) / nt);
}

class Stopwatch {
 public:
  explicit Stopwatch(double& acc) : acc_(acc), t0_(omp_get_wtime()) {}
  ~Stopwatch() { acc_ += omp_get_wtime() - t0_; }

 private:
  double& acc_;
  double t0_;
};

}  // namespace

// ---------------------------------------------------------------- building

Model::Model(const std::vector<double>& xy, const std::vector<int32_t>& tri,
             const std::vector<int32_t>& body) {
  if (xy.size() % 2 != 0 || xy.empty()) bad("nodes must be an (N, 2) array with N >= 3");
  if (tri.size() % 3 != 0 || tri.empty()) bad("triangles must be an (M, 3) array with M >= 1");
  const int64_t n = int64_t(xy.size() / 2), m = int64_t(tri.size() / 3);
  if (n > INT32_MAX / 2 || m > INT32_MAX / 6) bad("mesh too large for 32-bit ids");
  if (int64_t(body.size()) != m)
    bad("body must have one id per triangle (" + std::to_string(m) + "), got " +
        std::to_string(body.size()));
  for (double v : xy)
    if (!std::isfinite(v)) bad("nodes must be finite");
  int32_t n_bodies = 0;
  for (int64_t t = 0; t < m; ++t) {
    if (body[t] < 0) bad("body ids must be >= 0 (triangle " + std::to_string(t) + ")");
    n_bodies = std::max(n_bodies, body[t] + 1);
    for (int c = 0; c < 3; ++c) {
      const int32_t id = tri[3 * t + c];
      if (id < 0 || id >= n)
        bad("triangle " + std::to_string(t) + " uses node " + std::to_string(id) +
            ": node ids must be in [0, " + std::to_string(n - 1) + "]");
    }
  }
  nodes_.resize(int32_t(n));
  for (int64_t i = 0; i < n; ++i) {
    nodes_.x[i] = nodes_.x0[i] = xy[2 * i];
    nodes_.y[i] = nodes_.y0[i] = xy[2 * i + 1];
  }
  tris_.resize(int32_t(m));
  std::copy(tri.begin(), tri.end(), tris_.node.begin());
  std::copy(body.begin(), body.end(), tris_.body.begin());
  for (int32_t t = 0; t < int32_t(m); ++t) {
    const int32_t a = tri[3 * t], b = tri[3 * t + 1], c = tri[3 * t + 2];
    const double A = element_reference(nodes_.x0[a], nodes_.y0[a], nodes_.x0[b], nodes_.y0[b],
                                       nodes_.x0[c], nodes_.y0[c], tris_.binv00[t],
                                       tris_.binv01[t], tris_.binv10[t], tris_.binv11[t]);
    double longest = 0.0;
    for (int k = 0; k < 3; ++k) {
      const int32_t p = tri[3 * t + k], q = tri[3 * t + (k + 1) % 3];
      longest = std::max(longest, std::hypot(nodes_.x0[q] - nodes_.x0[p], nodes_.y0[q] - nodes_.y0[p]));
    }
    // A sliver whose area is round-off of its edge lengths has no usable Dm^-1.
    if (!(A > 1e-10 * longest * longest))
      bad("triangle " + std::to_string(t) + " (nodes " + std::to_string(a) + ", " +
          std::to_string(b) + ", " + std::to_string(c) + ") has signed area " + num(A) +
          " m²: triangles must be counter-clockwise and not degenerate (area > 1e-10 x longest edge²)");
    tris_.area0[t] = A;
  }
  materials_.assign(n_bodies, Material{});
  rebuild_topology();
}

void Model::rebuild_topology() {
  const int32_t n = nodes_.size(), m = tris_.size();
  // Node -> corner gather list, corners in ascending slot order.
  gather_.start.assign(size_t(n) + 1, 0);
  for (int32_t s = 0; s < 3 * m; ++s) {
    const int32_t id = tris_.node[s];
    if (id < 0 || id >= n)
      bad("triangle " + std::to_string(s / 3) + " uses node " + std::to_string(id) +
          ": node ids must be in [0, " + std::to_string(n - 1) + "]");
    ++gather_.start[id + 1];
  }
  for (int32_t i = 0; i < n; ++i) {
    if (gather_.start[i + 1] == 0)
      bad("node " + std::to_string(i) + " is not used by any triangle (it would have no mass)");
    gather_.start[i + 1] += gather_.start[i];
  }
  gather_.slot.resize(size_t(3) * m);
  {
    std::vector<int32_t> fill(gather_.start.begin(), gather_.start.end() - 1);
    for (int32_t s = 0; s < 3 * m; ++s) gather_.slot[fill[tris_.node[s]]++] = s;
  }
  // Boundary edges of each body: used by one triangle of that body only. The
  // mesh may be continuous across bodies (freeze bonds), so count per body.
  std::vector<std::tuple<int32_t, int32_t, int32_t>> edges;
  edges.reserve(size_t(3) * m);
  for (int32_t t = 0; t < m; ++t)
    for (int c = 0; c < 3; ++c) {
      const int32_t a = tris_.node[3 * t + c], b = tris_.node[3 * t + (c + 1) % 3];
      edges.emplace_back(tris_.body[t], std::min(a, b), std::max(a, b));
    }
  std::sort(edges.begin(), edges.end());
  on_surface_.assign(n, 0);
  for (size_t i = 0; i < edges.size();) {
    size_t j = i + 1;
    while (j < edges.size() && edges[j] == edges[i]) ++j;
    if (j - i == 1) on_surface_[std::get<1>(edges[i])] = on_surface_[std::get<2>(edges[i])] = 1;
    i = j;
  }
  surface_tris_.clear();
  std::vector<uint8_t> body_used(materials_.size(), 0);
  for (int32_t t = 0; t < m; ++t) {
    body_used[tris_.body[t]] = 1;
    const int32_t* c = &tris_.node[3 * t];
    if (on_surface_[c[0]] || on_surface_[c[1]] || on_surface_[c[2]]) surface_tris_.push_back(t);
  }
  contact_possible_ = std::count(body_used.begin(), body_used.end(), 1) >= 2;
  prepared_ = false;
  stable_current_ = false;
}

int32_t Model::add_node(double x, double y, double x0, double y0, double vx, double vy) {
  const int32_t id = nodes_.size();
  nodes_.resize(id + 1);
  nodes_.x[id] = x;
  nodes_.y[id] = y;
  nodes_.x0[id] = x0;
  nodes_.y0[id] = y0;
  nodes_.vx[id] = vx;
  nodes_.vy[id] = vy;
  prepared_ = false;
  return id;
}

void Model::set_triangle_node(int32_t tri, int corner, int32_t node) {
  if (tri < 0 || tri >= tris_.size()) bad("tri must be in [0, " + std::to_string(tris_.size() - 1) + "]");
  if (corner < 0 || corner > 2) bad("corner must be 0, 1 or 2");
  if (node < 0 || node >= nodes_.size()) bad("node must be in [0, " + std::to_string(nodes_.size() - 1) + "]");
  tris_.node[3 * tri + corner] = node;
  prepared_ = false;
}

int32_t Model::split_off(int32_t node, int32_t body) {
  const int32_t id = add_node(nodes_.x[node], nodes_.y[node], nodes_.x0[node], nodes_.y0[node],
                              nodes_.vx[node], nodes_.vy[node]);
  for (int32_t j = gather_.start[node]; j < gather_.start[node + 1]; ++j) {
    const int32_t s = gather_.slot[j];
    if (tris_.body[s / 3] == body) tris_.node[s] = id;
  }
  for (BoundaryCondition& bc : bcs_)
    if (std::find(bc.nodes.begin(), bc.nodes.end(), node) != bc.nodes.end()) bc.nodes.push_back(id);
  return id;
}

void Model::regather_node(int32_t i) {
  gather_node(i, any_damping_, ext_.water(), ext_.buoyancy, ext_.drag_on(), ext_.gravity ? ext_.g : 0.0);
}

bool Model::node_touches_body(int32_t node, int32_t body) const {
  for (int32_t j = gather_.start[node]; j < gather_.start[node + 1]; ++j)
    if (tris_.body[gather_.slot[j] / 3] == body) return true;
  return false;
}

// ---------------------------------------------------------------- parameters

void Model::set_material(int32_t b, const Material& mat) {
  if (b < 0 || b >= n_bodies())
    bad("body must be in [0, " + std::to_string(n_bodies() - 1) + "] (got " + std::to_string(b) + ")");
  require_finite_positive("E", mat.E, "Pa");
  if (!(mat.nu >= 0.0 && mat.nu < 0.5)) bad("nu must be in [0, 0.5) (got " + num(mat.nu) + ")");
  require_finite_positive("rho", mat.rho, "kg/m³");
  require_finite_nonnegative("damping", mat.damping, "s");
  require_finite_nonnegative("viscosity", mat.viscosity, "Pa s");
  materials_[b] = mat;
  materials_[b].set = true;
  prepared_ = false;
  stable_current_ = false;
}

void Model::set_dt(double dt) {
  require_finite_positive("dt", dt, "s");
  dt_ = dt;
}

void Model::set_gravity(bool on, double g) {
  require_finite_nonnegative("g", g, "m/s²");
  ext_.gravity = on;
  ext_.g = g;
}

void Model::set_water(bool buoyancy, bool drag, double rho_w, double y_w, double c_w) {
  require_finite_nonnegative("rho_w", rho_w, "kg/m³");
  require_finite_nonnegative("c_w", c_w, "Pa s");
  if (!std::isfinite(y_w)) bad("y_w (water line) must be finite (got " + num(y_w) + ")");
  ext_.buoyancy = buoyancy;
  ext_.drag = drag;
  ext_.rho_w = rho_w;
  ext_.y_w = y_w;
  ext_.c_w = c_w;
  stable_current_ = false;
}

void Model::set_drag_model(DragModel model, double C_d) {
  require_finite_nonnegative("C_d", C_d, "");
  ext_.drag_model = model;
  ext_.C_d = C_d;
  stable_current_ = false;
}

void Model::set_contact(double penalty, double mu) {
  require_finite_positive("penalty", penalty, "Pa");
  require_finite_nonnegative("mu", mu, "");
  contact_params_.penalty = penalty;
  contact_params_.mu = mu;
  stable_current_ = false;
  // The contact part of mass scaling depends on the penalty.
  if (mass_scaling_dt_ > 0.0) prepared_ = false;
}

void Model::set_local_damping(double alpha) {
  if (!(alpha >= 0.0 && alpha < 1.0))
    throw std::invalid_argument("local_damping = " + std::to_string(alpha) + " is out of range: valid range [0, 1)");
  local_damping_ = alpha;
}

void Model::set_energy_tolerance(double tol) { require_finite_positive("energy_tolerance", tol, ""); energy_tolerance_ = tol; }

void Model::set_mass_scaling(double dt_target) {
  require_finite_nonnegative("mass_scaling_dt", dt_target, "s (0: off)");
  mass_scaling_dt_ = dt_target;
  prepared_ = false;  // masses change
  stable_current_ = false;
}

void Model::set_threads(int n) {
  if (n < 0) bad("threads must be >= 0 (0: OpenMP default)");
  threads_ = n;
}

// ---------------------------------------------------------------- boundary conditions

void Model::add_boundary_condition(const BoundaryCondition& bc) {
  const std::string where = "boundary condition '" + bc.name + "'";
  if (bc.nodes.empty()) bad(where + ": node set is empty");
  for (int32_t id : bc.nodes)
    if (id < 0 || id >= nodes_.size())
      bad(where + ": node id " + std::to_string(id) + " out of range [0, " +
          std::to_string(nodes_.size() - 1) + "]");
  if (!bc.x && !bc.y) bad(where + ": constrains no component (x and y both off)");
  if (!std::isfinite(bc.dir_x) || !std::isfinite(bc.dir_y)) bad(where + ": direction must be finite");
  bc.history.validate(where);
  for (const BoundaryCondition& other : bcs_) {
    if (other.name == bc.name) bad(where + ": name already used");
    for (int32_t a : bc.nodes)
      for (int32_t b : other.nodes)
        if (a == b && ((bc.x && other.x) || (bc.y && other.y)))
          bad(where + ": node " + std::to_string(a) + " is already constrained by '" + other.name + "'");
  }
  bcs_.push_back(bc);
  prepared_ = false;
}

void Model::clear_boundary_conditions() {
  bcs_.clear();
  prepared_ = false;
}

int32_t Model::find_boundary_condition(const std::string& name) const {
  for (size_t i = 0; i < bcs_.size(); ++i)
    if (bcs_[i].name == name) return int32_t(i);
  return -1;
}

void Model::build_constraints() {
  std::fill(nodes_.constrained.begin(), nodes_.constrained.end(), 0);
  std::fill(nodes_.r_x.begin(), nodes_.r_x.end(), 0.0);
  std::fill(nodes_.r_y.begin(), nodes_.r_y.end(), 0.0);
  for (const BoundaryCondition& bc : bcs_)
    for (int32_t id : bc.nodes) nodes_.constrained[id] |= (bc.x ? 1 : 0) | (bc.y ? 2 : 0);
}

void Model::reaction(const std::vector<int32_t>& ids, double& rx, double& ry) const {
  rx = ry = 0.0;
  for (int32_t id : ids) {
    if (id < 0 || id >= nodes_.size())
      bad("node id " + std::to_string(id) + " out of range [0, " + std::to_string(nodes_.size() - 1) + "]");
    rx += nodes_.r_x[id];
    ry += nodes_.r_y[id];
  }
}

// ---------------------------------------------------------------- state

void Model::set_positions(const std::vector<double>& x, const std::vector<double>& y) {
  if (int64_t(x.size()) != nodes_.size() || int64_t(y.size()) != nodes_.size())
    bad("positions must have one row per node (" + std::to_string(nodes_.size()) + ")");
  for (size_t i = 0; i < x.size(); ++i)
    if (!std::isfinite(x[i]) || !std::isfinite(y[i])) bad("positions must be finite");
  nodes_.x = x;
  nodes_.y = y;
  reset_energy();
}

void Model::set_velocities(const std::vector<double>& vx, const std::vector<double>& vy) {
  if (int64_t(vx.size()) != nodes_.size() || int64_t(vy.size()) != nodes_.size())
    bad("velocities must have one row per node (" + std::to_string(nodes_.size()) + ")");
  for (size_t i = 0; i < vx.size(); ++i)
    if (!std::isfinite(vx[i]) || !std::isfinite(vy[i])) bad("velocities must be finite");
  nodes_.vx = vx;
  nodes_.vy = vy;
  reset_energy();
}

void Model::reset_energy() { energy_ = EnergyLedger{}; }

void Model::restore_clock(double time, int64_t step_count) {
  if (!std::isfinite(time)) bad("time must be finite (got " + num(time) + ")");
  if (step_count < 0) bad("step_count must be >= 0 (got " + std::to_string(step_count) + ")");
  time_ = time;
  step_count_ = step_count;
}

size_t Model::memory_bytes() const {
  size_t b = nodes_.bytes() + tris_.bytes() + gather_.bytes() + on_surface_.capacity() +
             surface_tris_.capacity() * sizeof(int32_t) + partial_.capacity() * sizeof(double) +
             bonds_.memory_bytes();
  for (const BoundaryCondition& bc : bcs_) b += bc.nodes.capacity() * sizeof(int32_t);
  return b;
}

// ---------------------------------------------------------------- preparation

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
    std::fill(tris_.f_visc_corner.begin(), tris_.f_visc_corner.end(), 0.0);
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
// it: k is per body). The margin 1e-12 absorbs the round-off of squaring and
// taking the root again, so the stable step is not below the target.
void Model::scale_masses() {
  added_mass_ = 0.0;
  scaled_nodes_ = 0;
  total_mass_phys_ = 0.0;
  for (double m : nodes_.mass_phys) total_mass_phys_ += m;
  if (!(mass_scaling_dt_ > 0.0)) return;
  const double need = mass_scaling_dt_ / kTimeStepSafety;
  const double margin = 1.0 + 1e-12;
  std::vector<double>& M = nodes_.mass;
  const std::vector<double>& Mp = nodes_.mass_phys;
  for (int32_t t = 0; t < tris_.size(); ++t) {
    const double dt_e = element_damped_dt(nodes_, tris_, elem_mat_, t);
    if (dt_e >= need) continue;
    const double r = mass_ratio_for(element_undamped_dt(nodes_, tris_, elem_mat_, t),
                                    elem_mat_[tris_.body[t]].tau_eff(), need) * margin;
    for (int c = 0; c < 3; ++c) {
      const int32_t i = tris_.node[3 * t + c];
      M[i] = std::max(M[i], Mp[i] * r);
    }
  }
  if (contact_possible_) {
    std::vector<double> k;
    contact_critical_dt(contact_params_, contact_input(), &k);
    for (int32_t i = 0; i < nodes_.size(); ++i)
      if (k[i] > 0.0) M[i] = std::max(M[i], 0.5 * k[i] * need * need * margin);
  }
  for (int32_t i = 0; i < nodes_.size(); ++i)
    if (M[i] > Mp[i]) {
      added_mass_ += M[i] - Mp[i];
      ++scaled_nodes_;
    }
}

void Model::prepare_topology() {
  if (prepared_) return;
  rebuild_topology();  // node splitting may have appended nodes or moved corners
  compute_masses();
  build_constraints();
  stable_current_ = false;
  prepared_ = true;
}

StableStep Model::stable_step() {
  prepare_topology();
  if (!stable_current_) {
    const ContactStableStep contact =
        contact_possible_ ? contact_critical_dt(contact_params_, contact_input()) : ContactStableStep{};
    stable_ = stable_time_step(nodes_, tris_, elem_mat_, contact_possible_, contact, ext_, body_area0_);
    stable_.mass_scaling_dt = mass_scaling_dt_;
    stable_.added_mass = added_mass_;
    stable_.added_mass_fraction = total_mass_phys_ > 0.0 ? added_mass_ / total_mass_phys_ : 0.0;
    stable_.scaled_nodes = scaled_nodes_;
    stable_current_ = true;
  }
  return stable_;
}

bool Model::use_threads() const { return tris_.size() >= kMinParallelTriangles; }

void Model::prepare() {
  stable_step();
  const int nt = std::min(threads_ > 0 ? threads_ : omp_get_max_threads(), kMaxThreads);
  partial_.assign(size_t(nt) * kPartialStride, 0.0);
}

// ---------------------------------------------------------------- the time step

void Model::step(int64_t n) {
  if (n < 0) bad("n (number of steps) must be >= 0");
  prepare();
  if (!(dt_ > 0.0)) bad("dt is not set: call set(dt=...) with dt > 0 s");
  if (check_stable_dt_ && dt_ > stable_.dt)
    bad("dt = " + num17(dt_) + " s exceeds the stable step " + num17(stable_.dt) + " s (by " +
        num(100.0 * (dt_ / stable_.dt - 1.0)) + " %; the stable step is recomputed when bond points split): " +
        stable_.describe(tris_.body) +
        ". Reduce dt, or coarsen the governing elements / lower the penalty.");
  for (int64_t k = 0; k < n; ++k) {
    Stopwatch total(timings_.total);
    advance();
    ++timings_.steps;
  }
}

void Model::advance() {
  // (1) element internal forces and (6) gravity, buoyancy, drag: both depend
  // only on the state at t, so one pass computes them (half the thread
  // synchronisations of two passes).
  compute_body_forces();
  compute_contact_forces();     // (2) neighbour search, (3) normal contact forces
  check_freeze_bonds();         // (4) bond stress check (eqs 5-7), node splitting
  apply_cohesive_forces(true);  // (5) cohesive forces of opened bonds (eqs 8-12)
  assemble_forces();            // total of (1)-(6)
  apply_friction();             // (3b) Coulomb friction (eq 4), needs all forces above
  apply_boundary_conditions();  // fixed nodes, prescribed velocities, reactions
  update_positions();           // (7) central difference, work integration
  guard_stability();
}

void Model::evaluate() {
  prepare();
  compute_body_forces();
  compute_contact_forces();
  apply_cohesive_forces(false);
  assemble_forces();
  apply_friction();
  apply_boundary_conditions();
}

// The per-node sums of the corner forces (elastic, viscous, buoyancy) and the
// drag coefficient, in the fixed gather order, plus gravity and drag: the
// node's total of everything but contact, bonds and friction. Also used for a
// node that has just been split off (FreezeBonds::split_points).
void Model::gather_node(int32_t i, bool damping, bool water, bool buoy, bool drag, double g) {
  const int32_t* start = gather_.start.data();
  const int32_t* slot = gather_.slot.data();
  const double* fc = tris_.f_corner.data();
  const double* fvc = tris_.f_visc_corner.data();
  const double* fbc = tris_.f_buoy_corner.data();
  const double* kdt = tris_.drag_k_tri.data();
  Nodes& N = nodes_;
  double fx = 0.0, fy = 0.0, vx = 0.0, vy = 0.0, fb = 0.0, k = 0.0;
  for (int32_t j = start[i]; j < start[i + 1]; ++j) {
    const int32_t s = slot[j];
    fx += fc[2 * s];
    fy += fc[2 * s + 1];
    if (damping) {
      vx += fvc[2 * s];
      vy += fvc[2 * s + 1];
    }
    if (water) {
      if (buoy) fb += fbc[s];
      if (drag) k += kdt[s / 3];
    }
  }
  N.f_int_x[i] = fx;
  N.f_int_y[i] = fy;
  N.f_visc_x[i] = vx;
  N.f_visc_y[i] = vy;
  N.f_buoy_y[i] = fb;
  N.drag_k[i] = k;
  N.f_x[i] = fx - k * N.vx[i];
  // Weight from the physical mass: mass scaling adds inertia, not weight.
  N.f_y[i] = fy + fb - k * N.vy[i] - N.mass_phys[i] * g;
  N.f_coh_x[i] = N.f_coh_y[i] = 0.0;
}

void Model::compute_body_forces() {
  Stopwatch sw(timings_.elements);
  const int nt = int(partial_.size() / kPartialStride);
  const int32_t m = tris_.size(), n = nodes_.size();
  int32_t inverted[kMaxThreads];
  std::fill(inverted, inverted + kMaxThreads, -1);
  const bool damping = any_damping_;
  const bool water = ext_.water();
  const bool buoy = ext_.buoyancy, drag = ext_.drag_on();
  const double g = ext_.gravity ? ext_.g : 0.0;
  if (drag) body_drag_constants(nodes_, tris_, ext_, body_area0_, body_drag_);
  #pragma omp parallel num_threads(nt) if (use_threads())
  {
    const int tid = omp_get_thread_num(), team = omp_get_num_threads();
    int32_t b, e;
    block(m, tid, team, b, e);
    // (1) element forces and (6) water forces, per triangle.
    ElementSweep sweep;
    element_forces(nodes_, tris_, elem_mat_, damping, b, e, sweep);
    if (water) water_forces_on_triangles(nodes_, tris_, ext_, body_area0_, body_drag_, b, e);
    partial_[tid * kPartialStride] = sweep.elastic_energy;
    inverted[tid] = sweep.inverted;
    #pragma omp barrier
    // Gather corner forces onto nodes in the fixed gather order, add gravity
    // and drag: the total of everything but contact, bonds and friction.
    Nodes& N = nodes_;
    #pragma omp for schedule(static)
    for (int32_t i = 0; i < n; ++i) {
      gather_node(i, damping, water, buoy, drag, g);
      // Contact and cohesive passes add into these.
      N.f_con_x[i] = N.f_con_y[i] = 0.0;
    }
  }
  double u = 0.0;
  first_inverted_ = -1;
  for (int t = 0; t < nt; ++t) {
    u += partial_[t * kPartialStride];
    partial_[t * kPartialStride] = 0.0;
    if (first_inverted_ < 0) first_inverted_ = inverted[t];
  }
  energy_.elastic = u;
}

ContactInput Model::contact_input() const {
  ContactInput in;
  in.n_nodes = nodes_.size();
  in.x = nodes_.x.data();
  in.y = nodes_.y.data();
  in.vx = nodes_.vx.data();
  in.vy = nodes_.vy.data();
  in.mass = nodes_.mass.data();
  in.n_tri = tris_.size();
  in.tri = tris_.node.data();
  in.body = tris_.body.data();
  in.n_surface = int32_t(surface_tris_.size());
  in.surface_tris = surface_tris_.data();
  in.dt = dt_;
  in.threads = threads_;
  // Friction must see fixed and driven nodes as immovable (contact branch).
  in.constrained = nodes_.constrained.data();
  return in;
}

void Model::compute_contact_forces() {
  contact_work_step_ = 0.0;
  if (!contact_possible_) return;
  const double detection_before = contact_.timings().detection_s;
  const double t0 = omp_get_wtime();
  contact_.compute_normal(contact_params_, contact_input(), nodes_.f_con_x.data(), nodes_.f_con_y.data());
  const double wall = omp_get_wtime() - t0;
  // ContactTimings are read as cumulative seconds since the solver was made.
  const double detection = contact_.timings().detection_s - detection_before;
  timings_.contact_detection += detection;
  timings_.contact_forces += wall - detection;
  contact_work_step_ = contact_.stored_energy();
}

void Model::check_freeze_bonds() {  // (4) freeze_bonds.cpp
  Stopwatch sw(timings_.bonds);
  bonds_.check(*this);
}

void Model::apply_cohesive_forces(bool commit) {  // (5) freeze_bonds.cpp
  Stopwatch sw(timings_.bonds);
  bonds_.apply(*this, commit);
  if (!commit) return;
  // The ledger's cohesive term is the work done against the cohesive forces
  // (booked by update_positions); the part stored on the secant branches is
  // recoverable, so it moves from "dissipated" to "stored".
  const double stored = bonds_.stored();
  energy_.cohesive -= stored - energy_.cohesive_stored;
  energy_.cohesive_stored = stored;
}

void Model::assemble_forces() {
  // Serial: one pass of adds, cheaper than waking the threads again.
  Stopwatch sw(timings_.integration);
  Nodes& N = nodes_;
  const int32_t n = N.size();
  for (int32_t i = 0; i < n; ++i) {
    N.f_x[i] += N.f_con_x[i] + N.f_coh_x[i];
    N.f_y[i] += N.f_con_y[i] + N.f_coh_y[i];
  }
  N.f_pre_x = N.f_x;
  N.f_pre_y = N.f_y;
}

void Model::apply_friction() {
  if (!contact_possible_) return;
  const double t0 = omp_get_wtime();
  const double detection_before = contact_.timings().detection_s;
  const double power = contact_.apply_friction(contact_params_, contact_input(), nodes_.f_x.data(), nodes_.f_y.data());
  const double detection = contact_.timings().detection_s - detection_before;
  timings_.contact_detection += detection;
  timings_.contact_forces += omp_get_wtime() - t0 - detection;
  energy_.friction_solver += power * dt_;
}

void Model::apply_boundary_conditions() {
  // The boundary adds r = m (v_bc - v)/dt - f so that the update lands exactly
  // on the prescribed velocity; r is what the boundary pushes with.
  const double inv_dt = dt_ > 0.0 ? 1.0 / dt_ : 0.0;
  const double t_half = time_ + 0.5 * dt_;
  Nodes& N = nodes_;
  for (const BoundaryCondition& bc : bcs_) {
    const double s = bc.history.at(t_half);
    const double ux = bc.dir_x * s, uy = bc.dir_y * s;
    for (int32_t i : bc.nodes) {
      if (bc.x) {
        N.v_bc_x[i] = ux;
        N.r_x[i] = N.mass[i] * (ux - N.vx[i]) * inv_dt - N.f_x[i];
      }
      if (bc.y) {
        N.v_bc_y[i] = uy;
        N.r_y[i] = N.mass[i] * (uy - N.vy[i]) * inv_dt - N.f_y[i];
      }
    }
  }
}

void Model::update_positions() {
  Stopwatch sw(timings_.integration);
  const int nt = int(partial_.size() / kPartialStride);
  const int32_t n = nodes_.size();
  const double dt = dt_;
  const double g = ext_.gravity ? ext_.g : 0.0;
  const double alpha = local_damping_;
  #pragma omp parallel num_threads(nt) if (use_threads())
  {
    Nodes& N = nodes_;
    double ke = 0.0, ke_old = 0.0, p_visc = 0.0, p_con = 0.0, p_fric = 0.0, p_coh = 0.0;
    double p_local = 0.0;
    double p_grav = 0.0, p_buoy = 0.0, p_drag = 0.0, p_bc = 0.0, p_el_new = 0.0, p_el_old = 0.0;
    #pragma omp for schedule(static)
    for (int32_t i = 0; i < n; ++i) {
      const double m = N.mass[i];
      const double vox = N.vx[i], voy = N.vy[i];
      const uint8_t c = N.constrained[i];
      double dfx = 0.0, dfy = 0.0;  // local damping force
      if (alpha > 0.0) {
        const double fx = N.f_x[i], fy = N.f_y[i];
        if (!(c & 1) && fx * vox != 0.0) dfx = -alpha * std::fabs(fx) * (vox > 0.0 ? 1.0 : -1.0);
        if (!(c & 2) && fy * voy != 0.0) dfy = -alpha * std::fabs(fy) * (voy > 0.0 ? 1.0 : -1.0);
      }
      const double vnx = (c & 1) ? N.v_bc_x[i] : vox + dt * (N.f_x[i] + dfx) / m;
      const double vny = (c & 2) ? N.v_bc_y[i] : voy + dt * (N.f_y[i] + dfy) / m;
      N.vx[i] = vnx;
      N.vy[i] = vny;
      N.x[i] += dt * vnx;
      N.y[i] += dt * vny;
      // Midpoint-rule power of each force with v(t) = (v^{n-1/2} + v^{n+1/2})/2.
      const double bx = 0.5 * (vox + vnx), by = 0.5 * (voy + vny);
      const double elx = N.f_int_x[i] - N.f_visc_x[i], ely = N.f_int_y[i] - N.f_visc_y[i];
      ke += m * (vnx * vnx + vny * vny);
      ke_old += m * (vox * vox + voy * voy);
      p_visc += N.f_visc_x[i] * bx + N.f_visc_y[i] * by;
      p_local += dfx * bx + dfy * by;
      p_con += N.f_con_x[i] * bx + N.f_con_y[i] * by;
      p_fric += (N.f_x[i] - N.f_pre_x[i]) * bx + (N.f_y[i] - N.f_pre_y[i]) * by;
      p_coh += N.f_coh_x[i] * bx + N.f_coh_y[i] * by;
      p_grav -= N.mass_phys[i] * g * by;  // the weight's power (physical mass)
      p_buoy += N.f_buoy_y[i] * by;
      p_drag -= N.drag_k[i] * (vox * bx + voy * by);
      p_bc += N.r_x[i] * bx + N.r_y[i] * by;
      p_el_new += elx * vnx + ely * vny;
      p_el_old += elx * vox + ely * voy;
    }
    double* p = &partial_[omp_get_thread_num() * kPartialStride];
    p[0] = ke; p[1] = ke_old; p[2] = p_visc; p[3] = p_con; p[4] = p_fric; p[5] = p_coh;
    p[6] = p_grav; p[7] = p_buoy; p[8] = p_drag; p[9] = p_bc; p[10] = p_el_new; p[11] = p_el_old;
    p[12] = p_local;
  }
  double s[13] = {0};
  for (int t = 0; t < nt; ++t)
    for (int k = 0; k < 13; ++k) {
      s[k] += partial_[t * kPartialStride + k];
      partial_[t * kPartialStride + k] = 0.0;
    }
  EnergyLedger& E = energy_;
  if (!E.started) {
    // Bookkeeping starts at x^{-1/2} = x^0 - dt v^{-1/2}/2, where the
    // midpoint-rule work starts: move U^0 there to first order.
    E.initial = 0.5 * s[1] + E.elastic + 0.5 * dt * s[11];
    E.started = true;
  }
  E.kinetic = 0.5 * s[0];
  E.damping -= dt * (s[2] + s[12]);
  E.contact -= dt * s[3];
  E.friction -= dt * s[4];
  E.cohesive -= dt * s[5];
  E.work_gravity += dt * s[6];
  E.work_buoyancy += dt * s[7];
  E.drag -= dt * s[8];
  E.work_boundary += dt * s[9];
  // The works cover the motion up to x^{n+1/2}; so must the elastic energy.
  E.elastic_midstep = E.elastic - 0.5 * dt * s[10];
  E.contact_solver = contact_work_step_;  // the contact module's current potential energy
  time_ += dt;
  ++step_count_;
}

// ---------------------------------------------------------------- stability guard

int32_t Model::body_of_node(int32_t node) const {
  if (node < 0 || size_t(node) + 1 >= gather_.start.size()) return -1;
  return tris_.body[gather_.slot[gather_.start[node]] / 3];
}

void Model::fail(const std::string& what, int32_t node, int32_t tri) const {
  std::ostringstream o;
  o.precision(6);
  o << "run stopped at step " << step_count_ << " (t = " << time_ << " s): " << what;
  if (node >= 0)
    o << "; at node " << node << " of body " << body_of_node(node) << ", position ("
      << nodes_.x[node] << ", " << nodes_.y[node] << ") m, initially (" << nodes_.x0[node]
      << ", " << nodes_.y0[node] << ") m";
  if (tri >= 0) {
    const int32_t* c = &tris_.node[3 * tri];
    o << "; at triangle " << tri << " of body " << tris_.body[tri] << ", centroid ("
      << (nodes_.x[c[0]] + nodes_.x[c[1]] + nodes_.x[c[2]]) / 3.0 << ", "
      << (nodes_.y[c[0]] + nodes_.y[c[1]] + nodes_.y[c[2]]) / 3.0 << ") m";
  }
  o << ". dt = " << dt_ << " s, stable estimate " << stable_.dt << " s.";
  throw InstabilityError(o.str());
}

void Model::guard_stability() {
  Stopwatch sw(timings_.integration);
  const EnergyLedger& E = energy_;
  const int32_t n = nodes_.size();
  if (!std::isfinite(E.kinetic) || !std::isfinite(E.elastic) || !std::isfinite(E.residual())) {
    const char* which = !std::isfinite(E.kinetic) ? "kinetic" : !std::isfinite(E.elastic) ? "elastic" : "contact/work";
    for (int32_t i = 0; i < n; ++i) {
      const Nodes& N = nodes_;
      if (!std::isfinite(N.x[i]) || !std::isfinite(N.y[i]) || !std::isfinite(N.vx[i]) ||
          !std::isfinite(N.vy[i]) || !std::isfinite(N.f_x[i]) || !std::isfinite(N.f_y[i])) {
        const char* what = !std::isfinite(N.f_con_x[i]) || !std::isfinite(N.f_con_y[i])
                               ? "contact force"
                           : !std::isfinite(N.f_int_x[i]) || !std::isfinite(N.f_int_y[i])
                               ? "internal force"
                               : "force/velocity";
        fail(std::string("non-finite ") + what + " (" + which + " energy not finite)", i, -1);
      }
    }
    fail(std::string("non-finite ") + which + " energy", -1, -1);
  }
  // Two energy checks. (a) The balance residual (stored energy moved to the
  // half step, as the works are): sensitive (O(dt²) in a sound run), catches
  // energy made by a force, e.g. a non-conservative contact. (b) The plain
  // stored energy KE + U + contact against what the sources supplied: the
  // central difference conserves a shadow energy even when unstable, so (a)
  // is blind to a time-step instability, while (b) sees it grow. In a stable
  // run the plain energy of a mode can exceed the shadow energy by
  // 1/(1 - (w dt/2)²), 5x at 0.9 of the critical step (and a start from rest
  // in that mode reaches it), so (b) fires above kGrowthFactor = 10x the
  // energy flows; an unstable mode grows 5-20x per step and is caught within
  // a step or two.
  const double residual = E.residual(), scale = E.scale();
  const double flows = std::fabs(E.initial) + std::fabs(E.work_gravity) + std::fabs(E.work_buoyancy) +
                       std::fabs(E.work_boundary) + std::fabs(E.dissipated());
  const double excess = E.kinetic + E.elastic + E.contact + E.dissipated() - E.initial - E.supplied();
  const bool growth = excess > kGrowthFactor * flows;
  const bool imbalance = residual > energy_tolerance_ * scale && scale > 0.0;
  if (check_energy_ && (growth || imbalance)) {
    // Where: the node with the most kinetic energy, the triangle with the
    // highest strain energy density.
    int32_t node = 0, tri = 0;
    double kmax = -1.0, umax = -1.0;
    for (int32_t i = 0; i < n; ++i) {
      const double k = nodes_.mass[i] * (nodes_.vx[i] * nodes_.vx[i] + nodes_.vy[i] * nodes_.vy[i]);
      if (k > kmax) { kmax = k; node = i; }
    }
    for (int32_t t = 0; t < tris_.size(); ++t) {
      const double u = element_strain_energy(nodes_, tris_, elem_mat_, t) / tris_.area0[t];
      if (u > umax) { umax = u; tri = t; }
    }
    const char* which = E.kinetic >= E.elastic && E.kinetic >= E.contact ? "kinetic"
                        : E.elastic >= E.contact ? "elastic" : "contact";
    const std::string test =
        growth ? "stored energy exceeds the energy supplied by " + num(excess) +
                     " J/m, more than 10 x all energy flows so far (" + num(flows) + " J/m)"
               : "balance residual " + num(residual) + " J/m > energy_tolerance " +
                     num(energy_tolerance_) + " x " + num(scale) + " J/m";
    fail(std::string(which) + " energy grew without an energy source: kinetic " + num(E.kinetic) +
             ", elastic " + num(E.elastic) + ", contact " + num(E.contact) + " J/m; " + test +
             "; largest kinetic energy at the node, largest strain energy density in the triangle below",
         node, tri);
  }
  if (first_inverted_ >= 0)
    fail("element inverted (det F <= 0): the mesh has collapsed, usually a too large dt or penalty overlap",
         -1, first_inverted_);
}

}  // namespace engine
