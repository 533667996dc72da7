#include "insertion/classify_points.h"

#include <algorithm>

namespace ndtom {

namespace {

inline void widen(CellIndex& lo, CellIndex& hi, const CellIndex& c) {
  lo = cellwiseMin(lo, c);
  hi = cellwiseMax(hi, c);
}

/// What classifying a point reads, loaded once per thread.
struct Limits {
  const GridGeometry& geometry;
  Eigen::Vector3d origin;
  double inv_resolution, min_range, max_range;
  double far_limit;  ///< kMaxRayCells cells: the longest ray traced
};

/// Drops bad points (counted by reason, in this order), truncates far ones at max_range.
/// Sets the ray's end and its cell and adds the ray's L1 length to `length` unless rejected.
inline PointKind classify(const Eigen::Vector3d& p, const Limits& limits, Eigen::Vector3d& end,
                          CellIndex& cell, double& length, InsertionReport& report) {
  const Eigen::Vector3d scaled = p * limits.inv_resolution;
  // One test for the common case, inside the grid with a margin; false for NaN and inf too.
  if (!(scaled.array().abs() < double(kMaxCellIndex - 1)).all()) {
    if (!p.allFinite()) {
      ++report.rejected_non_finite;
      return PointKind::kRejected;
    }
    if (!limits.geometry.inRange(p)) {
      ++report.rejected_out_of_grid;
      return PointKind::kRejected;
    }
  }
  const Eigen::Vector3d ray = p - limits.origin;
  const double range = ray.norm();
  if (range == 0.0 || range < limits.min_range) {
    ++report.rejected_too_close;
    return PointKind::kRejected;
  }
  if (std::min(range, limits.max_range) > limits.far_limit) {
    ++report.rejected_too_far;
    return PointKind::kRejected;
  }
  // Both ends inside the supported range, so every cell between them is too.
  if (range <= limits.max_range) {
    end = p;
    cell = GridGeometry::floorCell(scaled);
    length += ray.lpNorm<1>();
    ++report.hits;
    return PointKind::kHit;
  }
  end = limits.origin + ray * (limits.max_range / range);
  cell = limits.geometry.cellOf(end);
  length += (end - limits.origin).lpNorm<1>();
  ++report.truncated;
  return PointKind::kTruncated;
}

// A thread's chunk of the points: whole pieces of kRayPieces (their lengths are per piece).
void setChunks(size_t n, size_t threads, ClassifiedPoints& out) {
  constexpr size_t kPieces = ClassifiedPoints::kRayPieces;
  out.chunk_starts.resize(threads + 1);
  for (size_t t = 0; t <= threads; ++t)
    out.chunk_starts[t] = partRange(n, kPieces, partRange(kPieces, threads, t).first).first;
}

}  // namespace

void classifyPoints(const ScanContext& scan, const Eigen::Vector3d* points, size_t n,
                    ClassifiedPoints& out, InsertionReport& report) {
  constexpr size_t kPieces = ClassifiedPoints::kRayPieces;
  out.kinds.resize(n);
  out.ends.resize(n);
  out.end_cells.resize(n);
  struct alignas(64) Part {  // own cache line
    InsertionReport report;
    CellIndex lo{kMaxCellIndex, kMaxCellIndex, kMaxCellIndex};
    CellIndex hi{-kMaxCellIndex, -kMaxCellIndex, -kMaxCellIndex};
  };
  const size_t threads = scan.threadsFor(n, kMinPointsPerThread);
  std::vector<Part> parts(threads);
  setChunks(n, threads, out);
  const Limits limits{scan.geometry, scan.origin, scan.geometry.invResolution(),
                      scan.options.min_range, scan.options.max_range,
                      kMaxRayCells * scan.geometry.resolution()};
  scan.pool.run(threads, [&](size_t t) {
    InsertionReport counts;
    CellIndex lo = parts[t].lo, hi = parts[t].hi;  // in registers, not stored per point
    const auto [first_piece, last_piece] = partRange(kPieces, threads, t);
    for (size_t piece = first_piece; piece < last_piece; ++piece) {
      const auto [begin, end] = partRange(n, kPieces, piece);
      double length = 0;
      for (size_t i = begin; i < end; ++i) {
        out.kinds[i] = classify(points[i], limits, out.ends[i], out.end_cells[i], length, counts);
        if (out.kinds[i] != PointKind::kRejected) widen(lo, hi, out.end_cells[i]);
      }
      out.piece_lengths[piece] = length;
    }
    parts[t].report = counts;
    parts[t].lo = lo, parts[t].hi = hi;
  });
  out.ends_lo = parts[0].lo;
  out.ends_hi = parts[0].hi;
  out.used_before.assign(1, 0);
  for (const Part& part : parts) {
    out.used_before.push_back(out.used_before.back() + part.report.pointsUsed());
    report += part.report;
    widen(out.ends_lo, out.ends_hi, part.lo);
    widen(out.ends_lo, out.ends_hi, part.hi);
  }
  out.used = out.used_before.back();
}

void listHits(const ScanContext& scan, const std::vector<std::vector<Eigen::Vector3d>>& parts,
              ClassifiedPoints& out) {
  out.ends.clear();
  for (const std::vector<Eigen::Vector3d>& part : parts)
    out.ends.insert(out.ends.end(), part.begin(), part.end());
  const size_t n = out.ends.size();
  out.kinds.assign(n, PointKind::kHit);
  out.end_cells.resize(n);
  out.ends_lo = {kMaxCellIndex, kMaxCellIndex, kMaxCellIndex};
  out.ends_hi = {-kMaxCellIndex, -kMaxCellIndex, -kMaxCellIndex};
  for (size_t i = 0; i < n; ++i) {  // as classify(): floorCell of the scaled hit
    out.end_cells[i] = GridGeometry::floorCell(out.ends[i] * scan.geometry.invResolution());
    widen(out.ends_lo, out.ends_hi, out.end_cells[i]);
  }
  // Chunks as classification's, every point used: sorting's threads take them.
  setChunks(n, scan.threadsFor(n, kMinPointsPerThread), out);
  out.used_before = out.chunk_starts;
  out.piece_lengths.fill(0.0);  // no rays: the hits' rays were walked where they were classified
  out.used = n;
}

}  // namespace ndtom
