// The programs' clocks: wall time since a start, and CPU time, which beside wall time shows
// whether another process took the core (CPU < wall on one thread) or threads ran in parallel
// (CPU > wall).
#pragma once

#include <chrono>

namespace ndtom::apps {

/// Wall seconds from `start` to now (steady clock).
inline double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

/// CPU seconds used by all threads of this process so far (CLOCK_PROCESS_CPUTIME_ID).
double processCpuSeconds();
/// CPU seconds used by the calling thread so far (CLOCK_THREAD_CPUTIME_ID).
double threadCpuSeconds();

}  // namespace ndtom::apps
