// Resident memory of this process, from Linux's /proc/self: for the summaries' memory
// figures and the benchmark's peak RSS increase per run.
#pragma once

#include <cstddef>

namespace ndtom::apps {

/// VmRSS, the resident set size now, in bytes; 0 if unknown.
size_t currentRssBytes();
/// VmHWM, the largest resident set size since the start or the last successful
/// resetPeakRss(), in bytes; 0 if unknown.
size_t peakRssBytes();
/// Returns freed heap to the system, then resets VmHWM to the current RSS (Linux >= 4.0).
/// False if the peak cannot be reset: peak increases measured after it mean nothing then.
bool resetPeakRss();

}  // namespace ndtom::apps
