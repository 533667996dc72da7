// Resident memory of this process (Linux /proc), to measure each run's peak RSS increase.
#pragma once

#include <cstddef>

namespace ndtom::bench {

/// VmRSS in bytes; 0 if unavailable.
size_t currentRssBytes();
/// VmHWM (peak RSS since start or since the last successful resetPeakRss) in bytes.
size_t peakRssBytes();
/// Returns freed heap to the system, then resets VmHWM to the current RSS (Linux ≥ 4.0).
/// False if the peak cannot be reset: deltas are then not meaningful.
bool resetPeakRss();

}  // namespace ndtom::bench
