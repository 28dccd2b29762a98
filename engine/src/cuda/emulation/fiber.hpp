// Fibers for the emulated lanes of a block (cuda_runtime.h): each lane runs
// on a stack of its own until __syncthreads, where it hands back to the
// scheduler. A switch saves and restores only what the x86-64 System V ABI
// keeps across a call (a call to the switch: the callee-saved registers), a
// few nanoseconds where ucontext's swapcontext makes a system call;
// elsewhere ucontext.
//
// A block's reduction switches between up to 1024 lanes at every barrier, so
// the stacks lie in one mapping on huge pages where the kernel gives them
// (one TLB entry for hundreds of stacks), their tops staggered so that they
// do not map onto the same cache sets.
#pragma once

#include <cstddef>
#include <memory>
#include <vector>

namespace cuda_emu {

class Fiber {
 public:
  using Entry = void (*)();
  Fiber(char* stack, size_t bytes, unsigned int index);
  ~Fiber();
  Fiber(const Fiber&) = delete;
  Fiber& operator=(const Fiber&) = delete;
  // Ready to run `entry` from its start on the next resume.
  void start(Entry entry);
  // Runs this fiber from where it stopped until it yields (or ends: its
  // entry then yields for good).
  void resume();
  // Back to the scheduler (called on this fiber's own stack).
  void yield();
  // Whether the lowest bytes of the stack are as start() left them: a
  // lane that ran past its stack has written there.
  bool stack_intact() const;

 private:
  char* stack_;
  size_t bytes_;
  unsigned int index_;
  void* sp_ = nullptr;         // this fiber's saved stack pointer (x86-64)
  void* caller_sp_ = nullptr;  // the scheduler's, while this fiber runs
  void* context_ = nullptr;    // ucontext_t pair (other processors)
};

// The fibers of the widest block so far, on one mapping.
class FiberPool {
 public:
  ~FiberPool();
  // Fiber t (t below the lanes reserved)
  Fiber& operator[](unsigned int t) { return *fibers_[t]; }
  // At least n fibers (a block's lanes; at most 1024)
  void reserve(unsigned int n);

 private:
  char* mapping_ = nullptr;
  size_t mapping_bytes_ = 0;
  std::vector<std::unique_ptr<Fiber>> fibers_;
};

}  // namespace cuda_emu
