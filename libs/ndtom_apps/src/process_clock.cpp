#include "ndtom_apps/process_clock.h"

#include <ctime>

namespace ndtom::apps {

double processCpuSeconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}

}  // namespace ndtom::apps
