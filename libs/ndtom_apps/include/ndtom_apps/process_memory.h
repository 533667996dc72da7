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

/// For batch programs that allocate and free the same large buffers every scan (a scan's
/// points, its counters, the outputs' meshes): freed memory stays in the heap for the next
/// allocation instead of going back to the kernel and being faulted in, zeroed, again. glibc
/// otherwise maps buffers above its (adaptive) threshold one by one and trims the heap's top.
/// Memory is then returned only at exit, so long-running programs and builds that bound
/// their memory do not call this.
void keepFreedHeapForReuse();

}  // namespace ndtom::apps
