// Stage 4 of a scan's insertion: N_e of Eq. 12, how many rays cross each cell without ending
// in it, counted by walking the rays through the grid. Private to the library.
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "insertion/classify_points.h"
#include "insertion/end_groups.h"
#include "insertion/scan_context.h"
#include "insertion/scan_counts.h"
#include "insertion/scan_part.h"

namespace ndtom {

/// The counts, one table per tracing thread; which thread walked a ray changes nothing in
/// the map (the apply stage sums the tables).
struct FreeCounts {
  std::vector<ScanCounts> tables;  ///< kept from scan to scan (their blocks are reused)
  size_t used = 1;                 ///< tables filled by this scan (>= 1)
  bool exchanged = false;          ///< this scan's counts were traded (count_exchange.h)
  std::vector<std::vector<uint32_t>> outgoing, incoming;  ///< their messages, per process

  void reset() {
    if (tables.empty()) tables.resize(1);  // tables[0] takes the union even without tracing
    used = 1;
  }
};

/// Walks a ray per used point of `points` (RayMode::PerPoint) or per group of `groups` (to
/// its mean end, weighted by its count), from the sensor, counting into `out`; the rays cast
/// and cells visited go to `report`. The tables together add at most `blocks_left` blocks,
/// else BlockLimitReached is thrown. A distributed build's process (`part`, else nullptr) ends
/// with the counts of its own tiles only: with part->exchange it walks a share of the rays
/// whole and trades counts (throwing std::runtime_error if another process failed), else it
/// walks the stretches of every ray through its tiles.
void traceFreeRays(const ScanContext& scan, const ScanPart* part, const ClassifiedPoints& points,
                   const EndGroups& groups, std::atomic<int64_t>& blocks_left, FreeCounts& out,
                   InsertionReport& report);

}  // namespace ndtom
