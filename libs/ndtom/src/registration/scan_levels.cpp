#include "registration/scan_levels.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cstdint>

#include "support/radix_sort.h"

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

// Bits that hold values 0 .. span.
int bitsFor(uint64_t span) {
  int bits = 0;
  while (bits < 64 && (span >> bits) != 0) ++bits;
  return bits;
}

// Below this many items a part, waking a thread costs more than the part's work.
constexpr size_t kMinItemsPerThread = 2048;

using KeyedCells = std::vector<std::pair<CellIndex, uint32_t>>;

// Sorts (cell, index) pairs by cell (x major, as CellIndex's operator<), then index. Where the
// cells' box and the indices fit one 64-bit word (a scan spans a few thousand cells a side),
// a radix sort of the words: linear, and 8 bytes per item to move.
void sortByCell(KeyedCells& keyed, Threads threads) {
  if (keyed.empty()) return;
  const size_t n = keyed.size(), parts = threads.forItems(n, kMinItemsPerThread);
  std::vector<std::pair<CellIndex, CellIndex>> boxes(parts);
  threads.pool.run(parts, [&](size_t t) {
    const auto [begin, end] = partRange(n, parts, t);
    CellIndex lo = keyed[begin].first, hi = lo;
    for (size_t i = begin; i < end; ++i)
      for (int a = 0; a < 3; ++a) {
        lo[a] = std::min(lo[a], keyed[i].first[a]);
        hi[a] = std::max(hi[a], keyed[i].first[a]);
      }
    boxes[t] = {lo, hi};
  });
  CellIndex lo = boxes[0].first, hi = boxes[0].second;
  for (const auto& [part_lo, part_hi] : boxes)
    for (int a = 0; a < 3; ++a) {
      lo[a] = std::min(lo[a], part_lo[a]);
      hi[a] = std::max(hi[a], part_hi[a]);
    }
  int bits[3];
  for (int a = 0; a < 3; ++a) bits[a] = bitsFor(uint64_t(int64_t(hi[a]) - lo[a]));
  const int index_bits = bitsFor(n);
  const int key_bits = bits[0] + bits[1] + bits[2];
  if (key_bits + index_bits > 64 || key_bits == 0) {
    std::sort(keyed.begin(), keyed.end(), [](const auto& a, const auto& b) {
      return a.first < b.first || (a.first == b.first && a.second < b.second);
    });
    return;
  }
  std::vector<uint64_t> words(n), buffer;
  threads.pool.run(parts, [&](size_t t) {
    const auto [begin, end] = partRange(n, parts, t);
    for (size_t i = begin; i < end; ++i) {
      const CellIndex& c = keyed[i].first;
      const uint64_t key = (uint64_t(int64_t(c.x) - lo.x) << (bits[1] + bits[2])) |
                           (uint64_t(int64_t(c.y) - lo.y) << bits[2]) |
                           uint64_t(int64_t(c.z) - lo.z);
      words[i] = key << index_bits | keyed[i].second;  // indices ascend: the sort is stable
    }
  });
  radixSortByBits(words, buffer, index_bits, key_bits, threads.pool, parts);
  KeyedCells sorted(n);
  const uint64_t index_mask = (uint64_t(1) << index_bits) - 1;
  threads.pool.run(parts, [&](size_t t) {
    const auto [begin, end] = partRange(n, parts, t);
    for (size_t i = begin; i < end; ++i) sorted[i] = keyed[words[i] & index_mask];
  });
  keyed.swap(sorted);
}

// The items keyed by `cellOf(i)` for i < n, sorted by cell.
template <class CellOf>
KeyedCells keyedByCell(size_t n, CellOf&& cellOf, Threads threads) {
  KeyedCells keyed(n);
  const size_t parts = threads.forItems(n, kMinItemsPerThread);
  threads.pool.run(parts, [&](size_t t) {
    const auto [begin, end] = partRange(n, parts, t);
    for (size_t i = begin; i < end; ++i) keyed[i] = {cellOf(i), uint32_t(i)};
  });
  sortByCell(keyed, threads);
  return keyed;
}

// Where each run of equal cells of sorted `keyed` begins, then keyed.size().
std::vector<size_t> runStarts(const KeyedCells& keyed, Threads threads) {
  const size_t n = keyed.size(), parts = threads.forItems(n, kMinItemsPerThread);
  auto isStart = [&](size_t i) { return i == 0 || keyed[i].first != keyed[i - 1].first; };
  std::vector<size_t> counts(parts + 1, 0);
  threads.pool.run(parts, [&](size_t t) {
    const auto [begin, end] = partRange(n, parts, t);
    size_t starts_here = 0;  // counted locally: neighbouring parts' counts share a cache line
    for (size_t i = begin; i < end; ++i) starts_here += isStart(i);
    counts[t + 1] = starts_here;
  });
  for (size_t t = 0; t < parts; ++t) counts[t + 1] += counts[t];
  std::vector<size_t> starts(counts[parts] + 1);
  threads.pool.run(parts, [&](size_t t) {
    const auto [begin, end] = partRange(n, parts, t);
    size_t next = counts[t];
    for (size_t i = begin; i < end; ++i)
      if (isStart(i)) starts[next++] = i;
  });
  starts.back() = n;
  return starts;
}

// out[g] = makeCell(g, begin, end) for each run g of equal cells [begin, end) of `keyed`.
template <class MakeCell>
std::vector<ScanCell> cellsOfRuns(const KeyedCells& keyed, Threads threads, MakeCell&& makeCell) {
  const std::vector<size_t> starts = runStarts(keyed, threads);
  const size_t runs = starts.size() - 1;
  std::vector<ScanCell> out(runs);
  // A run's work is a few points: spread the runs as thinly as the items.
  const size_t parts = threads.forItems(runs, kMinItemsPerThread / 8);
  threads.pool.run(parts, [&](size_t t) {
    const auto [first, last] = partRange(runs, parts, t);
    for (size_t g = first; g < last; ++g) out[g] = makeCell(starts[g], starts[g + 1]);
  });
  return out;
}

}  // namespace

std::vector<ScanCell> groupPoints(const std::vector<Eigen::Vector3d>& points, double cell_size,
                                  Threads threads) {
  const KeyedCells keyed = keyedByCell(
      points.size(), [&](size_t i) { return cellOfPoint(points[i], cell_size); }, threads);
  return cellsOfRuns(keyed, threads, [&](size_t begin, size_t end) {
    thread_local std::vector<Eigen::Vector3d> members;
    members.clear();
    for (size_t i = begin; i < end; ++i) members.push_back(points[keyed[i].second]);
    return ScanCell{keyed[begin].first, CellStats::fromPoints(members)};
  });
}

std::vector<ScanCell> groupPoints(const std::vector<Eigen::Vector3d>& points, double cell_size) {
  WorkerPool pool;  // one thread: run() calls back directly, no thread is started
  return groupPoints(points, cell_size, Threads{pool, 1});
}

std::vector<ScanCell> regroup(const std::vector<ScanCell>& cells, double cell_size,
                              Threads threads) {
  const KeyedCells keyed = keyedByCell(
      cells.size(), [&](size_t i) { return cellOfPoint(cells[i].stats.relative_mean, cell_size); },
      threads);
  return cellsOfRuns(keyed, threads, [&](size_t begin, size_t end) {
    ScanCell merged{keyed[begin].first, CellStats{}};
    for (size_t i = begin; i < end; ++i) merged.stats.merge(cells[keyed[i].second].stats);
    return merged;
  });
}

std::vector<ScanLevel> buildScanLevels(const std::vector<Eigen::Vector3d>& points,
                                       const std::vector<double>& resolutions,
                                       const RegistrationOptions& options,
                                       const Regularization& regularization, Threads threads) {
  const bool p2d = options.method == RegistrationMethod::P2D;
  const double scale = p2d ? options.voxel_ratio : 1.0;
  std::vector<ScanLevel> levels(resolutions.size());
  std::vector<ScanCell> cells;
  for (size_t k = resolutions.size(); k-- > 0;) {  // fine to coarse
    const double cell_size = scale * resolutions[k];
    cells = k + 1 == resolutions.size() ? groupPoints(points, cell_size, threads)
                                        : regroup(cells, cell_size, threads);
    ScanLevel& level = levels[k];
    if (p2d) {
      std::vector<Eigen::Vector3d> centroids;
      centroids.reserve(cells.size());
      for (const ScanCell& c : cells) centroids.push_back(c.stats.relative_mean);
      level.points = spreadSubset(centroids, options.max_points);
      continue;
    }
    // Each part's Gaussians in cell order, the parts in order: the same list for any threads.
    const size_t parts = threads.forItems(cells.size(), 256);
    std::vector<std::vector<ScanGaussian>> part_gaussians(parts);
    threads.pool.run(parts, [&](size_t t) {
      const auto [begin, end] = partRange(cells.size(), parts, t);
      for (size_t i = begin; i < end; ++i)
        if (cells[i].stats.hasGaussian())
          part_gaussians[t].push_back(scanGaussian(cells[i].stats, regularization));
    });
    for (const std::vector<ScanGaussian>& part : part_gaussians)
      level.gaussians.insert(level.gaussians.end(), part.begin(), part.end());
  }
  return levels;
}

std::vector<ScanLevel> buildScanLevels(const std::vector<Eigen::Vector3d>& points,
                                       const std::vector<double>& resolutions,
                                       const RegistrationOptions& options,
                                       const Regularization& regularization) {
  WorkerPool pool;  // one thread: run() calls back directly, no thread is started
  return buildScanLevels(points, resolutions, options, regularization, Threads{pool, 1});
}

}  // namespace ndtom::registration
