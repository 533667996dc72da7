// Stage 4 of a scan's insertion: N_e of Eq. 12, how many rays cross each cell without ending
// in it, counted by walking the rays through the grid. Private to the library.
#pragma once

#include <Eigen/Core>
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
  /// Exchanges (count_exchange.h) this process has still to take part in for this scan.
  int exchanges_left = 0;
  std::vector<std::vector<uint32_t>> outgoing, incoming;  ///< their messages, per process
  /// Per-point rays shared out: a process classifies a share of the scan's points and walks
  /// their rays. Per process: the hits this one classified in its tiles (sent with the
  /// counts), and after the exchange the hits that process classified in this one's tiles
  /// (hits_from[own rank]: this one's own), in the scan's order.
  std::vector<std::vector<Eigen::Vector3d>> hits_to, hits_from;

  void reset() {
    if (tables.empty()) tables.resize(1);  // tables[0] takes the union even without tracing
    used = 1;
  }
};

/// Walks a ray per used point of `points` (RayMode::PerPoint) or per group of `groups` (to
/// its mean end, weighted by its count), from the sensor, counting into `out`; the rays cast
/// and cells visited go to `report`. The tables together add at most `blocks_left` blocks,
/// else BlockLimitReached is thrown. A distributed build's process (`part`, else nullptr) ends
/// with the counts of its own tiles only: with part->exchange it walks rays whole and trades
/// counts (throwing std::runtime_error if another process failed or sent a malformed
/// message), else it walks the stretches of every ray through its tiles. Trading, with
/// per-point rays `points` is the process's share of the scan: it walks all their rays, sends
/// their hits to the owners of their tiles (out.hits_from gets the hits of its own tiles) and
/// adds the others' point counts to `report`; with per-group rays it walks a share of them.
void traceFreeRays(const ScanContext& scan, const ScanPart* part, const ClassifiedPoints& points,
                   const EndGroups& groups, std::atomic<int64_t>& blocks_left, FreeCounts& out,
                   InsertionReport& report);

/// One of this scan's exchanges (count_exchange.h), counted off `counts.exchanges_left`.
/// Throws std::runtime_error, leaving no exchange to take part in, if any process failed.
void exchangeOrStop(CountExchange& exchange, FreeCounts& counts,
                    const std::vector<std::vector<uint32_t>>& outgoing,
                    std::vector<std::vector<uint32_t>>& incoming);

}  // namespace ndtom
