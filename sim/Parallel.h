// The one way sim/ runs loops in parallel (STYLE.md rule 4). Each iteration writes only its own
// element, so results do not depend on how OpenMP splits the range: runs are bit-identical for a
// fixed scene (and, since no reduction crosses threads, for any thread count).
#pragma once

#include <omp.h>
#include <cstddef>

namespace sph {

// Calls body(i) for i in [0, n) on all OpenMP threads, static schedule.
template <class Body>
void parallelFor(std::size_t n, Body&& body) {
  const long long count = static_cast<long long>(n);
#pragma omp parallel for schedule(static)
  for (long long i = 0; i < count; ++i) body(static_cast<std::size_t>(i));
}

// Like parallelFor, but hands out chunks dynamically: for loops whose iterations differ a lot in
// cost (cells of a neighbour grid). Still deterministic because iterations do not share output.
template <class Body>
void parallelForDynamic(std::size_t n, std::size_t chunk, Body&& body) {
  const long long count = static_cast<long long>(n);
  const int c = static_cast<int>(chunk);
#pragma omp parallel for schedule(dynamic, c)
  for (long long i = 0; i < count; ++i) body(static_cast<std::size_t>(i));
}

inline int threadCount() {
  return omp_get_max_threads();
}
inline int threadIndex() {
  return omp_get_thread_num();
}
// The most threads a run may ask for: 4 x the processors OpenMP may use here. More only costs
// (each thread needs a stack, every barrier waits for all of them), and libgomp fails at some
// point above (50,000 threads: "Thread creation failed"; 100,000: a crash), so `--threads` and a
// sweep's `threads` are refused beyond this.
inline int maxThreadCount() {
  return 4 * omp_get_num_procs();
}
inline void setThreadCount(int n) {
  if (n > 0) omp_set_num_threads(n);
}

}  // namespace sph
