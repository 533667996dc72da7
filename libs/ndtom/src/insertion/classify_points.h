// Stage 1 of a scan's insertion: what each input point is (a hit, a ray truncated at
// max_range, or rejected), where its ray ends and in which cell. Private to the library.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "insertion/scan_context.h"
#include "ndtom/map/cell_index.h"
#include "ndtom/map/insertion_report.h"

namespace ndtom {

enum class PointKind : uint8_t { kRejected, kTruncated, kHit };

struct ClassifiedPoints {
  /// The points are cut in this many near-equal contiguous pieces: classification's threads
  /// take whole pieces, and tracing shares the rays among its threads by the pieces' lengths.
  static constexpr size_t kRayPieces = 256;
  static_assert(kRayPieces >= size_t(ScanOptions::kMaxThreads), "a piece per thread");

  /// Per input point: its kind and, unless rejected, its ray end (the hit point, or the
  /// max-range end of a truncated ray, world frame) and that end's cell.
  std::vector<PointKind> kinds;
  std::vector<Eigen::Vector3d> ends;
  std::vector<CellIndex> end_cells;
  /// Chunk t, classified by one thread, is points [chunk_starts[t], chunk_starts[t + 1]);
  /// used_before[t] of the used points come before it.
  std::vector<size_t> chunk_starts, used_before;
  /// Per piece, its rays' summed L1 lengths (what walking them costs).
  std::array<double, kRayPieces> piece_lengths{};
  CellIndex ends_lo, ends_hi;  ///< bounding box of the ray ends' cells
  size_t used = 0;             ///< points not rejected

  size_t points() const { return kinds.size(); }
  size_t chunks() const { return chunk_starts.size() - 1; }
};

/// Classifies the n points from `points` into `out`, counting each point in `report` (hits,
/// truncated, or the reason it was rejected).
void classifyPoints(const ScanContext& scan, const Eigen::Vector3d* points, size_t n,
                    ClassifiedPoints& out, InsertionReport& report);
inline void classifyPoints(const ScanContext& scan, const std::vector<Eigen::Vector3d>& points,
                           ClassifiedPoints& out, InsertionReport& report) {
  classifyPoints(scan, points.data(), points.size(), out, report);
}

/// Hits classified elsewhere (a distributed build's processes, each a share of the scan), in
/// the order of `parts`, as classifying them would list them: the same ends and cells.
void listHits(const ScanContext& scan, const std::vector<std::vector<Eigen::Vector3d>>& parts,
              ClassifiedPoints& out);

}  // namespace ndtom
