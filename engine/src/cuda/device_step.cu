// Whole steps on the GPU (cuda/device_step.hpp): the body-force stage, the
// force assembly, the boundary conditions and the update, in Model::advance's
// order, on one stream. The two stages keep their own arrays for now (the
// comparisons of docs/gpu.md make them from a model one at a time), so the
// step copies the gathered forces into the update's arrays and the updated
// state back, on the GPU; one set of arrays for every stage comes with the
// contact stages.
#include "cuda/device_step.hpp"

#include <algorithm>
#include <cmath>
#include <set>
#include <string>

#include "common/input_errors.hpp"
#include "cuda/body_forces_impl.cuh"
#include "cuda/device_array.cuh"
#include "cuda/node_update_impl.cuh"
#include "cuda/stream.cuh"
#include "loads/boundary_kernel.hpp"
#include "model/assemble_kernel.hpp"
#include "model/model.hpp"
#include "model/step_sums.hpp"

namespace engine {

namespace {

constexpr int kBlock = 128;

int blocks(int64_t n) { return int((n + kBlock - 1) / kBlock); }

__global__ void assemble_kernel(AssembleArrays a, int32_t n) {
  const int32_t i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i < n) assemble_node(a, i);
}

__global__ void boundary_kernel(BoundaryComponent a, const int32_t* nodes, int32_t n, double v_bc, double inv_dt) {
  const int32_t k = blockIdx.x * blockDim.x + threadIdx.x;
  if (k < n) prescribe_component(a, nodes[k], v_bc, inv_dt);
}

// NodeWork's terms in the update's sums (cuda/node_update.cu), by name.
enum Term { kinetic2_new, kinetic2_old, viscous, local_damping, contact, friction, cohesive, gravity, buoyancy,
            drag, boundary, elastic_new, elastic_old, n_terms };

}  // namespace

struct DeviceStep::Impl {
  std::unique_ptr<DeviceBodyForces> forces;
  std::unique_ptr<DeviceNodeUpdate> update;
  std::vector<BoundaryCondition> bcs;
  std::vector<std::unique_ptr<DeviceArray<int32_t>>> bc_nodes;
  double dt = 0.0, time = 0.0;
  int64_t step_count = 0;
  EnergyLedger energy;
  cudaStream_t stream = nullptr;  // the body-force stage's; the update runs on it too
  // what a step copies back: the update's sums, the strain energy, the first inverted element
  double* host_sums = nullptr;  // pinned, n_terms + 1
  int32_t* host_inverted = nullptr;

  DeviceBodyForces::Impl& f() { return *forces->impl_; }
  DeviceNodeUpdate::Impl& u() { return *update->impl_; }

  void copy(DeviceArray<double>& to, const DeviceArray<double>& from) {
    cuda_check(cudaMemcpyAsync(to.data(), from.data(), from.size() * sizeof(double), cudaMemcpyDeviceToDevice,
                               stream), "copy on the GPU");
  }

  void one_step() {
    DeviceBodyForces::Impl& F = f();
    DeviceNodeUpdate::Impl& U = u();
    const int32_t n = U.n;
    F.launch();  // (1) elements, (6) gravity, buoyancy, drag, gathered onto the nodes
    copy(U.f_int_x, F.f_int_x);
    copy(U.f_int_y, F.f_int_y);
    copy(U.f_visc_x, F.f_visc_x);
    copy(U.f_visc_y, F.f_visc_y);
    copy(U.f_buoy_y, F.f_buoy_y);
    copy(U.drag_k, F.drag_k);
    copy(U.f_x, F.f_x);
    copy(U.f_y, F.f_y);
    copy(U.f_coh_x, F.f_coh_x);
    copy(U.f_coh_y, F.f_coh_y);
    // the total before friction (no contact: f_con stays zero)
    const AssembleArrays a{U.f_x.data(),     U.f_y.data(),     U.f_con_x.data(), U.f_con_y.data(),
                           U.f_coh_x.data(), U.f_coh_y.data(), U.f_pre_x.data(), U.f_pre_y.data()};
    assemble_kernel<<<blocks(n), kBlock, 0, stream>>>(a, n);
    // the boundary conditions at the step's midpoint, as Model::apply_boundary_conditions
    const double inv_dt = dt > 0.0 ? 1.0 / dt : 0.0;
    const double t_half = time + 0.5 * dt;
    const BoundaryComponent cx{U.mass.data(), U.vx.data(), U.f_x.data(), U.v_bc_x.data(), U.r_x.data()};
    const BoundaryComponent cy{U.mass.data(), U.vy.data(), U.f_y.data(), U.v_bc_y.data(), U.r_y.data()};
    for (size_t k = 0; k < bcs.size(); ++k) {
      const BoundaryCondition& bc = bcs[k];
      const double s = bc.history.at(t_half);
      const int32_t m = int32_t(bc.nodes.size());
      // the CPU sets x, then y, per node; the components are apart, so the order is moot
      if (bc.x) boundary_kernel<<<blocks(m), kBlock, 0, stream>>>(cx, bc_nodes[k]->data(), m, bc.dir_x * s, inv_dt);
      if (bc.y) boundary_kernel<<<blocks(m), kBlock, 0, stream>>>(cy, bc_nodes[k]->data(), m, bc.dir_y * s, inv_dt);
    }
    U.launch();  // (7) the central difference and the ledger's sums
    copy(F.x, U.x);  // the state the next step's forces read
    copy(F.y, U.y);
    copy(F.vx, U.vx);
    copy(F.vy, U.vy);
    cuda_check(cudaMemcpyAsync(host_sums, U.sums.data(), n_terms * sizeof(double), cudaMemcpyDeviceToHost, stream),
               "copy from GPU");
    cuda_check(cudaMemcpyAsync(host_sums + n_terms, F.total.data(), sizeof(double), cudaMemcpyDeviceToHost, stream),
               "copy from GPU");
    cuda_check(cudaMemcpyAsync(host_inverted, F.inverted.data(), sizeof(int32_t), cudaMemcpyDeviceToHost, stream),
               "copy from GPU");
    cuda_check(cudaStreamSynchronize(stream), "GPU step");
    book();
  }

  // The ledger as Model::update_positions books it (the CPU's sums of
  // gravity and drag are the negated sums of NodeWork's terms).
  void book() {
    const double* t = host_sums;
    StepSums s;
    s.kinetic2_new = t[kinetic2_new];
    s.kinetic2_old = t[kinetic2_old];
    s.viscous = t[viscous];
    s.local_damping = t[local_damping];
    s.contact = t[contact];
    s.friction = t[friction];
    s.cohesive = t[cohesive];
    s.gravity = -t[gravity];
    s.buoyancy = t[buoyancy];
    s.drag = -t[drag];
    s.boundary = t[boundary];
    s.elastic_new = t[elastic_new];
    s.elastic_old = t[elastic_old];
    energy.elastic = t[n_terms];
    energy.book_step(s, dt, 0.0);
    time += dt;
    ++step_count;
    const int32_t inverted = *host_inverted == 0x7f7f7f7f ? -1 : *host_inverted;
    const std::string at = "GPU step: run stopped at step " + std::to_string(step_count) + " (t = " + num(time) + " s): ";
    if (!std::isfinite(energy.kinetic) || !std::isfinite(energy.elastic))
      throw InstabilityError(at + "non-finite " + (std::isfinite(energy.kinetic) ? "elastic" : "kinetic") +
                             " energy; run the model on the CPU from the last state to find where");
    if (inverted >= 0)
      throw InstabilityError(at + "element " + std::to_string(inverted) +
                             " inverted (det F <= 0): the mesh has collapsed, usually a too large dt");
  }
};

DeviceStep::DeviceStep(Model& m) : impl_(new Impl) {
  m.step(0);  // prepared as Model::step prepares it: parameters, masses, dt against the stable step
  const Model& cm = m;  // the read access (a Model's writable views are its own)
  const std::vector<int32_t>& body = cm.triangles().body;
  if (std::set<int32_t>(body.begin(), body.end()).size() > 1)
    bad("the GPU step runs models of one body so far: this one has " +
        std::to_string(std::set<int32_t>(body.begin(), body.end()).size()) +
        " bodies, and contact between bodies is not on the GPU yet (docs/gpu.md)");
  if (cm.bonds().n_points() > 0)
    bad("the GPU step runs models without freeze bonds so far: this one has " +
        std::to_string(cm.bonds().n_points()) + " bond points (docs/gpu.md)");
  if (m.parameters().sleep.on) bad("the GPU step does not run the sleeping far field: set sleeping=False");
  Impl& d = *impl_;
  d.forces.reset(new DeviceBodyForces(m));
  d.update.reset(new DeviceNodeUpdate(m));
  // one stream for both stages
  d.stream = d.f().stream;
  cuda_check(cudaStreamDestroy(d.u().stream), "cudaStreamDestroy");
  d.u().stream = d.stream;
  for (DeviceArray<double>* a : {&d.u().f_con_x, &d.u().f_con_y})
    cuda_check(cudaMemset(a->data(), 0, a->size() * sizeof(double)), "memset");
  d.bcs = m.boundary_conditions();
  for (const BoundaryCondition& bc : d.bcs) {
    d.bc_nodes.emplace_back(new DeviceArray<int32_t>());
    d.bc_nodes.back()->upload(bc.nodes);
  }
  d.dt = m.dt();
  d.time = m.time();
  d.step_count = m.step_count();
  d.energy = m.energy();
  cuda_check(cudaMallocHost(&d.host_sums, (n_terms + 1) * sizeof(double)), "cudaMallocHost");
  cuda_check(cudaMallocHost(&d.host_inverted, sizeof(int32_t)), "cudaMallocHost");
}

DeviceStep::~DeviceStep() {
  Impl& d = *impl_;
  if (d.update) d.u().stream = nullptr;  // the body-force stage's: destroyed with it
  if (d.host_sums) cudaFreeHost(d.host_sums);
  if (d.host_inverted) cudaFreeHost(d.host_inverted);
}

void DeviceStep::step(int64_t n) {
  if (n < 0) bad("n (number of steps) must be >= 0");
  for (int64_t k = 0; k < n; ++k) impl_->one_step();
}

void DeviceStep::download(Model& m) {
  Impl& d = *impl_;
  cuda_check(cudaStreamSynchronize(d.stream), "GPU step");
  if (static_cast<const Model&>(m).nodes().size() != d.u().n) bad("download: the model has another mesh than the one the GPU step was made from");
  m.set_positions(d.u().x.download(), d.u().y.download());
  m.set_velocities(d.u().vx.download(), d.u().vy.download());
  m.restore_energy(d.energy);
  m.restore_clock(d.time, d.step_count);
}

void DeviceStep::reaction(const std::vector<int32_t>& nodes, double& rx, double& ry) {
  Impl& d = *impl_;
  cuda_check(cudaStreamSynchronize(d.stream), "GPU step");
  const std::vector<double> r_x = d.u().r_x.download(), r_y = d.u().r_y.download();
  rx = ry = 0.0;
  for (const int32_t i : nodes) {
    if (i < 0 || i >= d.u().n)
      bad("node id " + std::to_string(i) + " out of range [0, " + std::to_string(d.u().n - 1) + "]");
    rx += r_x[size_t(i)];
    ry += r_y[size_t(i)];
  }
}

double DeviceStep::time() const { return impl_->time; }
int64_t DeviceStep::step_count() const { return impl_->step_count; }
const EnergyLedger& DeviceStep::energy() const { return impl_->energy; }

}  // namespace engine
