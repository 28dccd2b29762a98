// Coulomb friction (paper eq 4, docs/model.md §3.2) with an exact stick state.
//
// Eq 4 as printed, f = -mu |f_c| v_t/|v_t|, is undefined at v_t = 0 and, in an
// explicit scheme, makes a block resting on a slope below the friction angle
// chatter and creep. Instead each touching pair carries a tangential force
// lambda, |lambda| <= mu |f_c|, chosen from the velocities the nodes will have
// at the end of this step, v' = v + dt f / m, where f already holds every other
// force of the step:
//   - if a force within the cone stops the tangential relative velocity at the
//     contact point, it is applied (stick: the block stays exactly at rest);
//   - otherwise lambda = -mu |f_c| sign(v_t') (slip: eq 4 with the end-of-step
//     sliding direction).
// Pairs that share nodes are coupled; projected Gauss-Seidel sweeps over the
// pairs (in pair order, so deterministic), warm-started from the previous
// step's forces, resolve that. The force acts at
// the contact point and is spread by the shape functions of both triangles,
// so it has zero resultant and zero moment over the pair.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>

#include "contact/contact.hpp"

namespace engine {
namespace {

// Sweeps are cheap (touching pairs only); 4 resolve the coupling between
// neighbouring pairs well enough, and the rest carries over to the next step.
constexpr int kSweeps = 4;

inline uint64_t pair_key(const ContactPair& c) {
  return (static_cast<uint64_t>(static_cast<uint32_t>(c.contactor)) << 32) |
         static_cast<uint32_t>(c.target);
}

inline double inverse_mass(double m) { return (m > 0.0 && std::isfinite(m)) ? 1.0 / m : 0.0; }

}  // namespace

double ContactSolver::apply_friction(const ContactParams& p, const ContactInput& in, double* fx,
                                     double* fy) {
  if (p.mu == 0.0 || pairs_.empty()) {
    prev_key_.clear();
    prev_lambda_.clear();
    return 0.0;
  }
  if (!(std::isfinite(in.dt) && in.dt > 0.0))
    throw std::invalid_argument("contact friction needs a time step dt > 0");
  const auto t0 = std::chrono::steady_clock::now();
  const double dt = in.dt;
  const size_t np = pairs_.size();
  if (wx_.size() < static_cast<size_t>(in.n_nodes)) {
    wx_.resize(in.n_nodes);
    wy_.resize(in.n_nodes);
    imx_.resize(in.n_nodes);
    imy_.resize(in.n_nodes);
  }
  if (lambda_.size() < np) {
    lambda_.resize(np);
    kinv_.resize(np);
  }

  // Per-component inverse masses (0 for an immovable or prescribed component)
  // and end-of-step velocities without friction, for the nodes that touch.
  for (size_t i = 0; i < np; ++i) {
    for (int k = 0; k < 6; ++k) {
      const int32_t n = pairs_[i].node[k];
      const double im = inverse_mass(in.mass[n]);
      const uint8_t cons = in.constrained ? in.constrained[n] : 0;
      imx_[n] = (cons & 1) ? 0.0 : im;
      imy_[n] = (cons & 2) ? 0.0 : im;
      if (cons & 1)
        wx_[n] = in.v_bc_x ? in.v_bc_x[n] : in.vx[n];
      else
        wx_[n] = in.vx[n] + dt * fx[n] * im;
      if (cons & 2)
        wy_[n] = in.v_bc_y ? in.v_bc_y[n] : in.vy[n];
      else
        wy_[n] = in.vy[n] + dt * fy[n] * im;
    }
  }
  // Inverse effective mass of each pair along its tangent: the change of the
  // tangential relative velocity per unit tangential force and unit dt.
  for (size_t i = 0; i < np; ++i) {
    const ContactPair& c = pairs_[i];
    const double tx2 = c.ny * c.ny, ty2 = c.nx * c.nx;
    double k = 0.0;
    for (int j = 0; j < 3; ++j) {
      const int32_t a = c.node[j], b = c.node[3 + j];
      k += c.nc[j] * c.nc[j] * (tx2 * imx_[a] + ty2 * imy_[a]);
      k += c.nt[j] * c.nt[j] * (tx2 * imx_[b] + ty2 * imy_[b]);
    }
    kinv_[i] = k;
    lambda_[i] = 0.0;
  }

  auto tangential_slip = [&](const ContactPair& c) {
    double ux = 0.0, uy = 0.0;
    for (int j = 0; j < 3; ++j) {
      ux += c.nc[j] * wx_[c.node[j]] - c.nt[j] * wx_[c.node[3 + j]];
      uy += c.nc[j] * wy_[c.node[j]] - c.nt[j] * wy_[c.node[3 + j]];
    }
    return -c.ny * ux + c.nx * uy;  // along the tangent (-ny, nx)
  };

  // Adds the change d of pair i's tangential force to the predicted velocities.
  auto push = [&](size_t i, double d) {
    const ContactPair& c = pairs_[i];
    const double tx = -c.ny, ty = c.nx;
    for (int j = 0; j < 3; ++j) {
      const int32_t a = c.node[j], b = c.node[3 + j];
      const double ia = dt * d * c.nc[j], ib = dt * d * c.nt[j];
      wx_[a] += ia * imx_[a] * tx;
      wy_[a] += ia * imy_[a] * ty;
      wx_[b] -= ib * imx_[b] * tx;
      wy_[b] -= ib * imy_[b] * ty;
    }
  };

  // Warm start from the force the same triangle pair carried last step: a
  // resting block needs nearly the same friction every step, so the sweeps
  // only correct it, and the iteration keeps converging across steps instead
  // of leaving a residual slip (creep) at a fixed sweep count.
  for (size_t i = 0; i < np; ++i) {
    const ContactPair& c = pairs_[i];
    const uint64_t key = pair_key(c);
    const auto it = std::lower_bound(prev_key_.begin(), prev_key_.end(), key);
    if (it == prev_key_.end() || *it != key || kinv_[i] == 0.0) continue;
    const double limit = p.mu * c.fn;
    const double lam = std::clamp(prev_lambda_[it - prev_key_.begin()], -limit, limit);
    lambda_[i] = lam;
    push(i, lam);
  }

  for (int sweep = 0; sweep < kSweeps; ++sweep) {
    for (size_t i = 0; i < np; ++i) {
      const ContactPair& c = pairs_[i];
      if (kinv_[i] == 0.0 || c.fn == 0.0) continue;
      const double limit = p.mu * c.fn;
      const double wt = tangential_slip(c);
      const double lam = std::clamp(lambda_[i] - wt / (dt * kinv_[i]), -limit, limit);
      const double d = lam - lambda_[i];
      if (d == 0.0) continue;
      lambda_[i] = lam;
      push(i, d);
    }
  }

  // Remember the forces by pair for the next step's warm start.
  order_.resize(np);
  for (size_t i = 0; i < np; ++i) order_[i] = {pair_key(pairs_[i]), lambda_[i]};
  std::sort(order_.begin(), order_.end());
  prev_key_.resize(np);
  prev_lambda_.resize(np);
  for (size_t i = 0; i < np; ++i) {
    prev_key_[i] = order_[i].first;
    prev_lambda_[i] = order_[i].second;
  }

  // Apply, and measure the power of friction with the velocities the nodes
  // will move with over this step (what the energy balance integrates).
  double dissipation = 0.0;
  for (size_t i = 0; i < np; ++i) {
    const ContactPair& c = pairs_[i];
    const double lam = lambda_[i];
    if (lam == 0.0) continue;
    const double tx = -c.ny * lam, ty = c.nx * lam;
    for (int j = 0; j < 3; ++j) {
      fx[c.node[j]] += c.nc[j] * tx;
      fy[c.node[j]] += c.nc[j] * ty;
      fx[c.node[3 + j]] -= c.nt[j] * tx;
      fy[c.node[3 + j]] -= c.nt[j] * ty;
    }
    dissipation -= lam * tangential_slip(c);
  }
  timings_.forces_s += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return dissipation;
}

}  // namespace engine
