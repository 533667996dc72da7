#include "registration/scan_levels.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cstdint>

#include "support/radix_sort.h"
#include "support/stage_clock.h"

namespace ndtom::registration {
namespace {

CellIndex cellOfPoint(const Eigen::Vector3d& p, double cell_size) {
  return GridGeometry::floorCell(p / cell_size);
}

// Evenly spread picks of at most `max_items` out of `items`.
template <class T>
std::vector<T> spreadSubset(const std::vector<T>& items, size_t max_items) {
  if (items.size() <= max_items) return items;
  std::vector<T> out;
  out.reserve(max_items);
  for (size_t k = 0; k < max_items; ++k) out.push_back(items[k * items.size() / max_items]);
  return out;
}

ScanGaussian scanGaussian(const CellStats& stats, const Regularization& regularization) {
  ScanGaussian g;
  g.mean = stats.relative_mean;
  g.covariance = regularizedCovariance(stats.covariance(), regularization);
  g.max_variance = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(g.covariance,
                                                                  Eigen::EigenvaluesOnly)
                       .eigenvalues()[2];
  return g;
}

}  // namespace

// Bits that hold values 0 .. span.
int bitsFor(uint64_t span) {
  int bits = 0;
  while (bits < 64 && (span >> bits) != 0) ++bits;
  return bits;
}

// Sorts (cell, index) pairs by cell (x major, as CellIndex's operator<), then index. Where the
// cells' box and the indices fit one 64-bit word (a scan spans a few thousand cells a side),
// a radix sort of the words: linear, and 8 bytes per item to move.
void sortByCell(std::vector<std::pair<CellIndex, uint32_t>>& keyed) {
  if (keyed.empty()) return;
  CellIndex lo = keyed[0].first, hi = lo;
  for (const auto& [c, i] : keyed)
    for (int a = 0; a < 3; ++a) {
      lo[a] = std::min(lo[a], c[a]);
      hi[a] = std::max(hi[a], c[a]);
    }
  int bits[3];
  for (int a = 0; a < 3; ++a) bits[a] = bitsFor(uint64_t(int64_t(hi[a]) - lo[a]));
  const int index_bits = bitsFor(keyed.size());
  const int key_bits = bits[0] + bits[1] + bits[2];
  if (key_bits + index_bits > 64 || key_bits == 0) {
    std::sort(keyed.begin(), keyed.end(), [](const auto& a, const auto& b) {
      return a.first < b.first || (a.first == b.first && a.second < b.second);
    });
    return;
  }
  std::vector<uint64_t> words(keyed.size()), buffer;
  for (size_t i = 0; i < keyed.size(); ++i) {
    const CellIndex& c = keyed[i].first;
    const uint64_t key = (uint64_t(int64_t(c.x) - lo.x) << (bits[1] + bits[2])) |
                         (uint64_t(int64_t(c.y) - lo.y) << bits[2]) | uint64_t(int64_t(c.z) - lo.z);
    words[i] = key << index_bits | keyed[i].second;  // indices ascend: the sort is stable
  }
  WorkerPool pool;  // one thread: run() calls back directly, no thread is started
  const SerialRegion serial;  // a profile counts it as serial, which it is
  radixSortByBits(words, buffer, index_bits, key_bits, pool, 1);
  const std::vector<std::pair<CellIndex, uint32_t>> original = keyed;
  const uint64_t index_mask = (uint64_t(1) << index_bits) - 1;
  for (size_t i = 0; i < words.size(); ++i) keyed[i] = original[words[i] & index_mask];
}

std::vector<ScanCell> groupPoints(const std::vector<Eigen::Vector3d>& points, double cell_size) {
  std::vector<std::pair<CellIndex, uint32_t>> keyed;
  keyed.reserve(points.size());
  for (uint32_t i = 0; i < points.size(); ++i)
    keyed.emplace_back(cellOfPoint(points[i], cell_size), i);
  sortByCell(keyed);
  std::vector<ScanCell> cells;
  std::vector<Eigen::Vector3d> members;
  for (size_t begin = 0; begin < keyed.size();) {
    size_t end = begin;
    members.clear();
    while (end < keyed.size() && keyed[end].first == keyed[begin].first)
      members.push_back(points[keyed[end++].second]);
    cells.push_back({keyed[begin].first, CellStats::fromPoints(members)});
    begin = end;
  }
  return cells;
}

std::vector<ScanCell> regroup(const std::vector<ScanCell>& cells, double cell_size) {
  std::vector<std::pair<CellIndex, uint32_t>> keyed;
  keyed.reserve(cells.size());
  for (uint32_t i = 0; i < cells.size(); ++i)
    keyed.emplace_back(cellOfPoint(cells[i].stats.relative_mean, cell_size), i);
  sortByCell(keyed);
  std::vector<ScanCell> out;
  for (const auto& [cell, i] : keyed) {
    if (out.empty() || out.back().cell != cell) out.push_back({cell, CellStats{}});
    out.back().stats.merge(cells[i].stats);
  }
  return out;
}

std::vector<ScanLevel> buildScanLevels(const std::vector<Eigen::Vector3d>& points,
                                       const std::vector<double>& resolutions,
                                       const RegistrationOptions& options,
                                       const Regularization& regularization) {
  const bool p2d = options.method == RegistrationMethod::P2D;
  const double scale = p2d ? options.voxel_ratio : 1.0;
  std::vector<ScanLevel> levels(resolutions.size());
  std::vector<ScanCell> cells;
  for (size_t k = resolutions.size(); k-- > 0;) {  // fine to coarse
    const double cell_size = scale * resolutions[k];
    cells = k + 1 == resolutions.size() ? groupPoints(points, cell_size) : regroup(cells, cell_size);
    ScanLevel& level = levels[k];
    if (p2d) {
      std::vector<Eigen::Vector3d> centroids;
      centroids.reserve(cells.size());
      for (const ScanCell& c : cells) centroids.push_back(c.stats.relative_mean);
      level.points = spreadSubset(centroids, options.max_points);
    } else {
      for (const ScanCell& c : cells)
        if (c.stats.hasGaussian()) level.gaussians.push_back(scanGaussian(c.stats, regularization));
    }
  }
  return levels;
}

}  // namespace ndtom::registration
