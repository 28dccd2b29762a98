// Wall time of a scope added to an accumulator (the step timings).
#pragma once
#include <omp.h>

namespace engine {

class Stopwatch {
 public:
  explicit Stopwatch(double& acc) : acc_(acc), t0_(omp_get_wtime()) {}
  ~Stopwatch() { acc_ += omp_get_wtime() - t0_; }
  Stopwatch(const Stopwatch&) = delete;
  Stopwatch& operator=(const Stopwatch&) = delete;

 private:
  double& acc_;
  double t0_;
};

}  // namespace engine
