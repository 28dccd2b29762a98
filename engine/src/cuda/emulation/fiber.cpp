// Fibers for the emulated lanes (fiber.hpp).
#include "fiber.hpp"

#include <sys/mman.h>

#include <cstdint>
#include <cstring>
#include <new>

#if !defined(__x86_64__)
#include <ucontext.h>
#endif

namespace cuda_emu {

namespace {
// a lane's stack: the kernels' frames are a few hundred bytes to a few KiB
constexpr size_t kStackBytes = 64 * 1024;
constexpr size_t kMaxLanes = 1024;  // a block's most
// the lowest bytes of each stack, written at start and checked after
constexpr size_t kGuardBytes = 64;
constexpr unsigned char kGuard = 0xa5;
}  // namespace

#if defined(__x86_64__)

// switch_stack(save, to): pushes the callee-saved registers on the current
// stack, stores the stack pointer in *save, loads `to` and pops the same from
// there. The floating-point control words are not switched: no lane changes
// its rounding or its exception masks (loading them costs more than the
// rest of the switch). A fiber's first resume "returns" into its entry
// (Fiber::start lays its stack out so).
extern "C" void cuda_emu_switch_stack(void** save, void* to);
asm(R"(
  .text
  .globl cuda_emu_switch_stack
  .hidden cuda_emu_switch_stack
  .type cuda_emu_switch_stack, @function
cuda_emu_switch_stack:
  pushq %rbp
  pushq %rbx
  pushq %r12
  pushq %r13
  pushq %r14
  pushq %r15
  movq %rsp, (%rdi)
  movq %rsi, %rsp
  popq %r15
  popq %r14
  popq %r13
  popq %r12
  popq %rbx
  popq %rbp
  ret
  .size cuda_emu_switch_stack, .-cuda_emu_switch_stack
)");

#endif

Fiber::Fiber(char* stack, size_t bytes, unsigned int index) : stack_(stack), bytes_(bytes), index_(index) {
#if !defined(__x86_64__)
  context_ = new ucontext_t[2];
#endif
}

Fiber::~Fiber() {
#if !defined(__x86_64__)
  delete[] static_cast<ucontext_t*>(context_);
#endif
}

bool Fiber::stack_intact() const {
  for (size_t k = 0; k < kGuardBytes; ++k)
    if (static_cast<unsigned char>(stack_[k]) != kGuard) return false;
  return true;
}

void Fiber::start(Entry entry) {
  std::memset(stack_, kGuard, kGuardBytes);
  // the top staggered by a multiple of 64 bytes that is not a power of two
  const size_t stagger = size_t(index_ % 61) * 64;  // cache lines: 61 sets of the 4 KiB stride
#if defined(__x86_64__)
  // from the (16-byte aligned) top: a zero return address for the entry
  // (it never returns), the entry as the switch's return address, six
  // registers
  auto* top = reinterpret_cast<uint64_t*>((reinterpret_cast<uintptr_t>(stack_) + bytes_ - stagger) & ~uintptr_t(15));
  uint64_t* sp = top;
  *--sp = 0;
  *--sp = reinterpret_cast<uint64_t>(entry);
  for (int k = 0; k < 6; ++k) *--sp = 0;
  sp_ = sp;
#else
  auto* c = static_cast<ucontext_t*>(context_);
  getcontext(&c[0]);
  c[0].uc_stack.ss_sp = stack_;
  c[0].uc_stack.ss_size = bytes_ - stagger;
  c[0].uc_link = nullptr;
  makecontext(&c[0], entry, 0);
#endif
}

#if defined(__x86_64__)
void Fiber::resume() { cuda_emu_switch_stack(&caller_sp_, sp_); }
void Fiber::yield() { cuda_emu_switch_stack(&sp_, caller_sp_); }
#else
void Fiber::resume() {
  auto* c = static_cast<ucontext_t*>(context_);
  swapcontext(&c[1], &c[0]);
}
void Fiber::yield() {
  auto* c = static_cast<ucontext_t*>(context_);
  swapcontext(&c[0], &c[1]);
}
#endif

FiberPool::~FiberPool() {
  fibers_.clear();
  if (mapping_) munmap(mapping_, mapping_bytes_);
}

void FiberPool::reserve(unsigned int n) {
  if (n <= fibers_.size()) return;
  if (!mapping_) {
    mapping_bytes_ = kMaxLanes * kStackBytes;
    void* p = mmap(nullptr, mapping_bytes_, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS | MAP_NORESERVE,
                   -1, 0);
    if (p == MAP_FAILED) throw std::bad_alloc();
    mapping_ = static_cast<char*>(p);
#ifdef MADV_HUGEPAGE
    madvise(mapping_, mapping_bytes_, MADV_HUGEPAGE);
#endif
  }
  while (fibers_.size() < n && fibers_.size() < kMaxLanes) {
    const unsigned int t = unsigned(fibers_.size());
    fibers_.emplace_back(new Fiber(mapping_ + size_t(t) * kStackBytes, kStackBytes, t));
  }
}

}  // namespace cuda_emu
