// The GPU backend's entry points in a build without a CUDA toolkit: each
// says so (the CPU engine is complete without it).
#include <stdexcept>

#include "cuda/body_forces.hpp"
#include "cuda/broad_phase.hpp"
#include "cuda/bond_check.hpp"
#include "cuda/cohesive_forces.hpp"
#include "cuda/contact_normal.hpp"
#include "cuda/device_memory.hpp"
#include "cuda/device_step.hpp"
#include "cuda/emulation_check.hpp"
#include "cuda/friction.hpp"
#include "cuda/node_update.hpp"

namespace engine {

namespace {
[[noreturn]] void no_gpu() {
  throw std::runtime_error(
      "this build has no GPU backend: no CUDA toolkit (nvcc) was found when it was built; "
      "install one and run `make build` again (docs/gpu.md)");
}
}  // namespace

bool cuda_built() { return false; }
bool cuda_emulated() { return false; }
std::map<std::string, double> cuda_emulation_check(const std::string&) { no_gpu(); }
std::string cuda_device_name() { return ""; }
DeviceMemoryCounts device_memory_counts() { return {}; }
size_t device_size_class(size_t) { no_gpu(); }

struct DeviceBodyForces::Impl {};
DeviceBodyForces::DeviceBodyForces(const Model&) { no_gpu(); }
DeviceBodyForces::~DeviceBodyForces() = default;
void DeviceBodyForces::upload_state(const Model&) { no_gpu(); }
void DeviceBodyForces::run() { no_gpu(); }
double DeviceBodyForces::time_per_run(int) { no_gpu(); }
std::vector<double> DeviceBodyForces::stage_times(int) { no_gpu(); }
BodyForceFields DeviceBodyForces::fields() { no_gpu(); }

struct DeviceBroadPhase::Impl {};
DeviceBroadPhase::DeviceBroadPhase(const Model&) { no_gpu(); }
DeviceBroadPhase::~DeviceBroadPhase() = default;
SearchedLayout DeviceBroadPhase::search(const Model&) { no_gpu(); }
double DeviceBroadPhase::seconds_per_search(const Model&, int) { no_gpu(); }

struct DeviceNodeUpdate::Impl {};
DeviceNodeUpdate::DeviceNodeUpdate(const Model&) { no_gpu(); }
DeviceNodeUpdate::~DeviceNodeUpdate() = default;
void DeviceNodeUpdate::run() { no_gpu(); }
double DeviceNodeUpdate::time_per_run(int) { no_gpu(); }
NodeUpdateFields DeviceNodeUpdate::fields() { no_gpu(); }

struct DeviceBondCheck::Impl {};
DeviceBondCheck::DeviceBondCheck(const Model&) { no_gpu(); }
DeviceBondCheck::~DeviceBondCheck() = default;
void DeviceBondCheck::run() { no_gpu(); }
double DeviceBondCheck::time_per_run(int) { no_gpu(); }
BondCheckFields DeviceBondCheck::fields() { no_gpu(); }

struct DeviceCohesiveForces::Impl {};
DeviceCohesiveForces::DeviceCohesiveForces(const Model&) { no_gpu(); }
DeviceCohesiveForces::~DeviceCohesiveForces() = default;
void DeviceCohesiveForces::run() { no_gpu(); }
double DeviceCohesiveForces::time_per_run(int) { no_gpu(); }
CohesiveForceFields DeviceCohesiveForces::fields() { no_gpu(); }
int32_t DeviceCohesiveForces::open_pairs() const { no_gpu(); }

struct DeviceContactNormal::Impl {};
DeviceContactNormal::DeviceContactNormal(const Model&) { no_gpu(); }
DeviceContactNormal::~DeviceContactNormal() = default;
void DeviceContactNormal::run() { no_gpu(); }
double DeviceContactNormal::time_per_run(int) { no_gpu(); }
ContactNormalFields DeviceContactNormal::fields() { no_gpu(); }
int64_t DeviceContactNormal::candidates() const { no_gpu(); }

struct DeviceFriction::Impl {};
DeviceFriction::DeviceFriction(const Model&, WarmStart) { no_gpu(); }
DeviceFriction::~DeviceFriction() = default;
void DeviceFriction::run() { no_gpu(); }
double DeviceFriction::time_per_run(int) { no_gpu(); }
FrictionFields DeviceFriction::fields() { no_gpu(); }
int32_t DeviceFriction::candidates() const { no_gpu(); }
void DeviceFriction::set_earlier_list(int32_t) { no_gpu(); }
void DeviceFriction::set_shared_nodes(int32_t) { no_gpu(); }

struct DeviceStep::Impl {};
DeviceStep::DeviceStep(Model&) { no_gpu(); }
DeviceStep::~DeviceStep() = default;
void DeviceStep::step(int64_t) { no_gpu(); }
void DeviceStep::download(Model&) { no_gpu(); }
void DeviceStep::reaction(const std::vector<int32_t>&, double&, double&) { no_gpu(); }
double DeviceStep::time() const { no_gpu(); }
int64_t DeviceStep::step_count() const { no_gpu(); }
int64_t DeviceStep::host_steps() const { no_gpu(); }
int64_t DeviceStep::remakes() const { no_gpu(); }
int64_t DeviceStep::graph_instantiations() const { no_gpu(); }
int64_t DeviceStep::graph_updates() const { no_gpu(); }
double DeviceStep::host_step_seconds() const { no_gpu(); }
double DeviceStep::make_seconds() const { no_gpu(); }
int64_t DeviceStep::list_rebuilds() const { no_gpu(); }
int64_t DeviceStep::colourings() const { no_gpu(); }
double DeviceStep::list_seconds() const { no_gpu(); }
const EnergyLedger& DeviceStep::energy() const { no_gpu(); }

}  // namespace engine
