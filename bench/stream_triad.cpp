// Memory bandwidth by thread count (STREAM's triad a = b + s c, bytes read
// and written counted), the ceiling the CPU engine's per-step streams of the
// node and corner arrays meet (bench/gpu_body_forces.py reads it beside the
// engine's parts; docs/gpu.md). Not project code: a measuring stick.
//   g++ -O3 -fopenmp bench/stream_triad.cpp -o /tmp/triad && /tmp/triad 1 2 4 8 16
#include <omp.h>

#include <cstdio>
#include <cstdlib>
#include <vector>

int main(int argc, char** argv) {
  // sizes: 4 MB per array (in cache), 17 MB (three arrays of 50 MB together:
  // the paper mesh's engine arrays are 35 MB) and 268 MB (memory)
  for (size_t n : {size_t(1) << 19, size_t(1) << 21, size_t(1) << 25}) {
    std::vector<double> a(n), b(n, 1.0), c(n, 2.0);
    for (int k = 1; k < argc; ++k) {
      const int threads = std::atoi(argv[k]);
      const int reps = n < (size_t(1) << 20) ? 2000 : n < (size_t(1) << 22) ? 200 : 20;
      double best = 1e30;
      for (int r = 0; r < reps; ++r) {
        const double t0 = omp_get_wtime();
        #pragma omp parallel for num_threads(threads) schedule(static)
        for (size_t i = 0; i < n; ++i) a[i] = b[i] + 3.0 * c[i];
        const double t = omp_get_wtime() - t0;
        if (t < best) best = t;
      }
      std::printf("triad %5.0f MB per array, %2d threads: %6.1f GB/s\n", n * 8 / 1e6, threads,
                  3.0 * n * 8 / best / 1e9);
    }
  }
  return 0;
}
