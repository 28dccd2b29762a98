// The CUDA runtime emulated on the CPU (cuda_runtime.h says what it keeps of
// a GPU and why). One host thread drives it, as the engine does.
#include <signal.h>
#include <sys/mman.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <deque>
#include <map>
#include <memory>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include "cuda_runtime.h"
#include "fiber.hpp"

namespace cuda_emu {

uint3 thread_idx{0, 0, 0}, block_idx{0, 0, 0};
dim3 block_dim, grid_dim;

using Work = std::function<void()>;

struct Stream {
  bool blocking = true;  // waited for by the legacy stream's copies
  std::deque<Work> queue;
  bool capturing = false;
  std::vector<Work> captured;
};
struct Event {
  Stream* stream = nullptr;
  double seconds = 0.0;
};
struct Graph {
  std::vector<Work> work;
};

namespace {

// ---- errors: a failed call returns its code; a stream's work that failed
// is said at the next wait, with what failed in words
cudaError_t last_error = cudaSuccess;
std::string fault;          // the failed work's message, until a wait says it
std::string fault_said;     // ... and after (cudaGetErrorString)

cudaError_t fail(cudaError_t e) {
  last_error = e;
  return e;
}

double now() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

// ---- device memory: one reserved range, readable and writable only while
// a stream's work runs; blocks handed out first-fit from a free list
constexpr size_t kArenaBytes = size_t(64) << 30;  // address space only (MAP_NORESERVE)
constexpr size_t kAlign = 256;
const size_t kPage = size_t(sysconf(_SC_PAGESIZE));
size_t padded(size_t bytes) { return std::max(kAlign, (bytes + kAlign - 1) / kAlign * kAlign); }
char* arena = nullptr;
size_t arena_top = 0;                    // bytes handed out so far from the start
std::multimap<size_t, size_t> free_blocks;  // size -> offset
std::map<size_t, size_t> used_blocks;       // offset -> size
bool device_open = false;
struct sigaction previous_segv {};

void on_segv(int sig, siginfo_t* info, void* context) {
  const char* a = static_cast<const char*>(info->si_addr);
  if (arena && a >= arena && a < arena + kArenaBytes && !device_open) {
    char msg[256];
    const int n = snprintf(msg, sizeof msg,
                           "GPU emulation: host code touched device memory (offset %zu of the device arena) "
                           "outside a stream's work: on a GPU this reads or writes an invalid address\n",
                           size_t(a - arena));
    if (n > 0) (void)!write(2, msg, size_t(n));
    abort();
  }
  // not ours: the handler before (or the default) takes it
  sigaction(SIGSEGV, &previous_segv, nullptr);
  (void)sig;
  (void)context;
}

void reserve_arena() {
  if (arena) return;
  void* p = mmap(nullptr, kArenaBytes, PROT_NONE, MAP_PRIVATE | MAP_ANONYMOUS | MAP_NORESERVE, -1, 0);
  if (p == MAP_FAILED) throw std::runtime_error("GPU emulation: cannot reserve the device arena");
  arena = static_cast<char*>(p);
  struct sigaction sa {};
  sa.sa_sigaction = on_segv;
  sa.sa_flags = SA_SIGINFO | SA_ONSTACK;
  sigemptyset(&sa.sa_mask);
  sigaction(SIGSEGV, &sa, &previous_segv);
}

void set_device_access(bool open) {
  if (open == device_open || !arena_top) {
    device_open = open;
    return;
  }
  mprotect(arena, arena_top, open ? PROT_READ | PROT_WRITE : PROT_NONE);
  device_open = open;
}

// Runs `w` (device memory in reach: the caller opened it); a failure is kept
// for the next wait.
void run_work(const Work& w) {
  try {
    w();
  } catch (const std::exception& e) {
    if (fault.empty()) fault = e.what();
  }
}

// Device memory in reach while a wait runs the work it waits for.
int access_depth = 0;
struct DeviceAccess {
  DeviceAccess() {
    if (access_depth++ == 0) set_device_access(true);
  }
  ~DeviceAccess() {
    if (--access_depth == 0) set_device_access(false);
  }
};

// ---- streams
Stream legacy_stream;  // stream 0
std::set<Stream*> streams;

Stream* stream_of(cudaStream_t s) { return s ? s : &legacy_stream; }

void drain(Stream* s) {
  if (s->queue.empty()) return;
  DeviceAccess open;
  while (!s->queue.empty()) {
    Work w = std::move(s->queue.front());
    s->queue.pop_front();
    run_work(w);
  }
}
void drain_all() {
  drain(&legacy_stream);
  for (Stream* s : streams) drain(s);
}
// A wait's answer: the failure of the work it ran, if any (said once: the
// emulation goes on after it, where a GPU's context would be lost).
cudaError_t waited() {
  if (fault.empty()) return cudaSuccess;
  fault_said = fault;
  fault.clear();
  return fail(cudaErrorLaunchFailure);
}
// A synchronous call on the legacy stream (cudaMemcpy, cudaMemset): after the
// blocking streams' work before it, now, and said at once.
// The work opens only the device memory it names (a copy's or a fill's
// range): opening the whole arena twice per copy cost more than the copies
// where a stage uploads a hundred arrays.
// The pages holding arena bytes [at, at + n) set to `prot`.
void protect_pages(size_t at, size_t n, int prot) {
  const size_t from = at / kPage * kPage;
  mprotect(arena + from, (at + n + kPage - 1) / kPage * kPage - from, prot);
}

struct RangeAccess {
  size_t at = 0, bytes = 0;
  RangeAccess(const void* p, size_t n) {
    const char* c = static_cast<const char*>(p);
    if (!arena || device_open || c < arena || c >= arena + arena_top || n == 0) return;
    at = size_t(c - arena);
    bytes = n;
    protect_pages(at, bytes, PROT_READ | PROT_WRITE);
  }
  ~RangeAccess() {
    if (bytes) protect_pages(at, bytes, PROT_NONE);
  }
};

cudaError_t run_on_legacy_stream(const Work& w, const void* a, const void* b, size_t bytes) {
  drain(&legacy_stream);
  for (Stream* s : streams)
    if (s->blocking) drain(s);
  RangeAccess open_a(a, bytes);
  RangeAccess open_b(b, bytes);
  run_work(w);
  return waited();
}

void enqueue(cudaStream_t st, Work w) {
  Stream* s = stream_of(st);
  if (s->capturing)
    s->captured.push_back(std::move(w));
  else
    s->queue.push_back(std::move(w));
}

// ---- a launch's lanes
struct Block {
  const std::function<void()>* lane = nullptr;
  FiberPool fibers;
  std::vector<char> done;
  unsigned int running = 0;  // the lane on a fiber now
  bool on_fiber = false;     // lanes run on fibers (else one after another, on the host stack)
  bool reached_barrier = false;
  int or_sum = 0, or_result = 0;  // __syncthreads_or's, this barrier's and the last one's
};
Block block;

void lane_entry() {
  run_work(*block.lane);
  block.done[block.running] = 1;
  for (;;) block.fibers[block.running].yield();
}

uint3 lane_coordinates(unsigned int t) {
  if (block_dim.y == 1 && block_dim.z == 1) return uint3{t, 0, 0};  // the backend's blocks
  return uint3{t % block_dim.x, (t / block_dim.x) % block_dim.y, t / (block_dim.x * block_dim.y)};
}

// Lanes 0..n-1 kept to their stacks (fiber.hpp), else a fault.
void check_stacks(unsigned int n) {
  for (unsigned int t = 0; t < n; ++t)
    if (!block.fibers[t].stack_intact()) throw std::runtime_error("GPU emulation: a lane ran past its stack");
}

// A block: lane 0 first, on a fiber. If it ends without a barrier, the
// kernel has none and the other lanes run one after another on the host
// stack (a lane that then reaches one belongs to a kernel whose lanes differ
// on barriers: said as a fault). Else every lane runs on a fiber, barrier by
// barrier: each live lane runs to its next __syncthreads (or its end), then
// the next round begins.
void run_block(unsigned int n) {
  block.reached_barrier = false;
  block.or_sum = block.or_result = 0;
  block.fibers.reserve(n);
  block.done.assign(n, 0);
  block.on_fiber = true;
  block.running = 0;
  thread_idx = lane_coordinates(0);
  block.fibers[0].start(lane_entry);
  block.fibers[0].resume();
  if (!block.reached_barrier) {
    check_stacks(1);
    block.on_fiber = false;
    for (unsigned int t = 1; t < n; ++t) {
      thread_idx = lane_coordinates(t);
      (*block.lane)();
    }
    return;
  }
  for (unsigned int t = 1; t < n; ++t) block.fibers[t].start(lane_entry);
  unsigned int first = 1;  // lane 0 waits at the first barrier already
  for (;;) {
    bool alive = first == 1;
    for (unsigned int t = first; t < n; ++t) {
      if (block.done[t]) continue;
      block.running = t;
      thread_idx = lane_coordinates(t);
      block.fibers[t].resume();
      alive = alive || !block.done[t];
    }
    if (!alive) return check_stacks(n);
    block.or_result = block.or_sum;  // every live lane is at the barrier
    block.or_sum = 0;
    first = 0;
  }
}

}  // namespace

void launch(cudaStream_t stream, dim3 grid, dim3 blk, std::function<void()> lane) {
  const unsigned long long lanes = 1ull * blk.x * blk.y * blk.z;
  if (lanes == 0 || lanes > 1024 || blk.z > 64 || grid.x == 0 || grid.y == 0 || grid.z == 0 || grid.y > 65535 ||
      grid.z > 65535) {
    fail(cudaErrorInvalidConfiguration);
    return;
  }
  enqueue(stream, [grid, blk, lane = std::move(lane)]() {
    grid_dim = grid;
    block_dim = blk;
    block.lane = &lane;
    const unsigned int n = unsigned(blk.x * blk.y * blk.z);
    for (unsigned int z = 0; z < grid.z; ++z)
      for (unsigned int y = 0; y < grid.y; ++y)
        for (unsigned int x = 0; x < grid.x; ++x) {
          block_idx = uint3{x, y, z};
          run_block(n);
          if (!fault.empty()) return;
        }
  });
}

void syncthreads() {
  if (!block.on_fiber)
    throw std::runtime_error(
        "GPU emulation: a kernel's lane reached __syncthreads where the block's lane 0 had ended without one: "
        "its lanes differ on barriers (undefined on a GPU)");
  block.reached_barrier = true;
  block.fibers[block.running].yield();
}

int syncthreads_or(int predicate) {
  if (predicate) block.or_sum = 1;
  syncthreads();
  return block.or_result;
}

void trap() {
  fputs("GPU emulation: a kernel called __trap() (on a GPU the launch fails with an error at the next wait)\n",
        stderr);
  abort();
}

}  // namespace cuda_emu

using namespace cuda_emu;

// ---- the runtime's calls

cudaError_t cudaGetDeviceCount(int* count) {
  *count = 1;
  return cudaSuccess;
}

cudaError_t cudaDeviceGetAttribute(int* value, cudaDeviceAttr attr, int device) {
  if (device != 0 || attr != cudaDevAttrMaxSharedMemoryPerBlockOptin) return fail(cudaErrorInvalidValue);
  *value = 227 * 1024;
  return cudaSuccess;
}

cudaError_t cudaGetDeviceProperties(cudaDeviceProp* p, int device) {
  if (device != 0) return fail(cudaErrorInvalidValue);
  std::memset(p, 0, sizeof *p);
  std::snprintf(p->name, sizeof p->name, "CPU emulation of the CUDA runtime (one thread; for tests)");
  p->multiProcessorCount = 1;
  p->maxThreadsPerBlock = 1024;
  p->warpSize = 32;
  p->totalGlobalMem = kArenaBytes;
  p->sharedMemPerBlock = 48 * 1024;
  p->major = 9;
  p->minor = 0;
  return cudaSuccess;
}

cudaError_t cudaGetLastError() {
  const cudaError_t e = last_error;
  last_error = cudaSuccess;
  return e;
}

const char* cudaGetErrorString(cudaError_t e) {
  switch (e) {
    case cudaSuccess: return "no error";
    case cudaErrorInvalidValue: return "invalid argument";
    case cudaErrorMemoryAllocation: return "out of memory";
    case cudaErrorInvalidConfiguration: return "invalid configuration argument";
    case cudaErrorLaunchFailure: return fault_said.empty() ? "unspecified launch failure" : fault_said.c_str();
    case cudaErrorStreamCaptureUnsupported: return "operation not permitted when stream is capturing";
  }
  return "unknown error";
}

cudaError_t cudaDeviceSynchronize() {
  drain_all();
  return waited();
}

cudaError_t cudaMalloc(void** p, size_t bytes) {
  reserve_arena();
  const size_t size = padded(bytes);
  size_t at;
  auto it = free_blocks.lower_bound(size);
  if (it != free_blocks.end() && it->first == size) {
    at = it->second;
    free_blocks.erase(it);
  } else {
    if (arena_top + size > kArenaBytes) return fail(cudaErrorMemoryAllocation);
    at = arena_top;
    arena_top += size;
  }
  used_blocks[at] = size;
  // fresh memory is not zero: every byte 0xff (doubles NaN, integers -1)
  if (device_open) {  // the new pages open as the rest
    protect_pages(at, size, PROT_READ | PROT_WRITE);
    std::memset(arena + at, 0xff, size);
  } else {
    RangeAccess open(arena + at, size);
    std::memset(arena + at, 0xff, size);
  }
  *p = arena + at;
  return cudaSuccess;
}

cudaError_t cudaFree(void* p) {
  if (!p) return cudaSuccess;
  drain_all();  // cudaFree waits for the device
  if (!arena || static_cast<char*>(p) < arena) return fail(cudaErrorInvalidValue);
  auto it = used_blocks.find(size_t(static_cast<char*>(p) - arena));
  if (it == used_blocks.end()) return fail(cudaErrorInvalidValue);
  const size_t at = it->first;
  free_blocks.emplace(it->second, at);
  used_blocks.erase(it);
  return waited();
}

cudaError_t cudaMallocHost(void** p, size_t bytes) {
  *p = std::aligned_alloc(kAlign, padded(bytes));
  return *p ? cudaSuccess : fail(cudaErrorMemoryAllocation);
}

cudaError_t cudaFreeHost(void* p) {
  drain_all();
  std::free(p);
  return waited();
}

cudaError_t cudaMemcpy(void* dst, const void* src, size_t bytes, cudaMemcpyKind) {
  return run_on_legacy_stream([=] { std::memcpy(dst, src, bytes); }, dst, src, bytes);
}

cudaError_t cudaMemcpyAsync(void* dst, const void* src, size_t bytes, cudaMemcpyKind, cudaStream_t s) {
  enqueue(s, [=] { std::memcpy(dst, src, bytes); });
  return cudaSuccess;
}

cudaError_t cudaMemset(void* p, int value, size_t bytes) {
  return run_on_legacy_stream([=] { std::memset(p, value, bytes); }, p, nullptr, bytes);
}

cudaError_t cudaMemsetAsync(void* p, int value, size_t bytes, cudaStream_t s) {
  enqueue(s, [=] { std::memset(p, value, bytes); });
  return cudaSuccess;
}

cudaError_t cudaStreamCreateWithFlags(cudaStream_t* s, unsigned int flags) {
  *s = new Stream();
  (*s)->blocking = !(flags & cudaStreamNonBlocking);
  streams.insert(*s);
  return cudaSuccess;
}

cudaError_t cudaStreamDestroy(cudaStream_t s) {
  if (!s || !streams.count(s)) return fail(cudaErrorInvalidValue);
  drain(s);  // its work still runs
  streams.erase(s);
  delete s;
  return cudaSuccess;
}

cudaError_t cudaStreamSynchronize(cudaStream_t s) {
  drain(stream_of(s));
  return waited();
}

cudaError_t cudaEventCreate(cudaEvent_t* e) {
  *e = new Event();
  return cudaSuccess;
}
cudaError_t cudaEventDestroy(cudaEvent_t e) {
  delete e;
  return cudaSuccess;
}
cudaError_t cudaEventRecord(cudaEvent_t e, cudaStream_t s) {
  e->stream = stream_of(s);
  enqueue(s, [e] { e->seconds = now(); });
  return cudaSuccess;
}
cudaError_t cudaEventSynchronize(cudaEvent_t e) {
  if (e->stream) drain(e->stream);
  return waited();
}
cudaError_t cudaEventElapsedTime(float* ms, cudaEvent_t a, cudaEvent_t b) {
  *ms = float(1e3 * (b->seconds - a->seconds));
  return cudaSuccess;
}

cudaError_t cudaStreamBeginCapture(cudaStream_t s, cudaStreamCaptureMode) {
  Stream* st = stream_of(s);
  if (st == &legacy_stream || st->capturing) return fail(cudaErrorStreamCaptureUnsupported);
  st->capturing = true;
  st->captured.clear();
  return cudaSuccess;
}
cudaError_t cudaStreamEndCapture(cudaStream_t s, cudaGraph_t* g) {
  Stream* st = stream_of(s);
  if (!st->capturing) return fail(cudaErrorInvalidValue);
  *g = new Graph{std::move(st->captured)};
  st->captured.clear();
  st->capturing = false;
  return cudaSuccess;
}
cudaError_t cudaGraphInstantiate(cudaGraphExec_t* exec, cudaGraph_t g, unsigned long long) {
  *exec = new Graph{g->work};
  return cudaSuccess;
}
cudaError_t cudaGraphLaunch(cudaGraphExec_t exec, cudaStream_t s) {
  for (const Work& w : exec->work) enqueue(s, w);
  return cudaSuccess;
}
cudaError_t cudaGraphDestroy(cudaGraph_t g) {
  delete g;
  return cudaSuccess;
}
cudaError_t cudaGraphExecDestroy(cudaGraphExec_t exec) {
  delete exec;
  return cudaSuccess;
}
// In place where the new graph has as many pieces of work (a GPU asks for
// the same nodes, of the same kinds, in the same order; the emulation's
// captured work does not record kinds), else refused as a GPU refuses: the
// caller instantiates afresh.
cudaError_t cudaGraphExecUpdate(cudaGraphExec_t exec, cudaGraph_t g, cudaGraphExecUpdateResultInfo* info) {
  if (!exec || !g) return fail(cudaErrorInvalidValue);
  const bool same = exec->work.size() == g->work.size();
  if (info) *info = cudaGraphExecUpdateResultInfo{same ? 0 : 1, nullptr, nullptr};
  if (!same) return fail(cudaErrorGraphExecUpdateFailure);
  exec->work = g->work;
  return cudaSuccess;
}
