// CPU time of this process, for the benchmarks: beside wall time it shows whether another
// process took the core (CPU < wall on one thread) or threads ran in parallel (CPU > wall).
#pragma once

namespace ndtom::apps {

/// CPU seconds used by all threads of this process so far (CLOCK_PROCESS_CPUTIME_ID).
double processCpuSeconds();

}  // namespace ndtom::apps
