// One block of the map's cells: private to the library (NdtMap holds them in a BlockGrid).
#pragma once

#include <algorithm>
#include <array>
#include <bitset>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "ndtom/map/block_grid.h"
#include "ndtom/map/cell_stats.h"
#include "ndtom/map/options.h"

namespace ndtom {

/// A block's cells, with the statistics of the few that have some packed in offset order:
/// most known cells are free space, so a per-cell slot would cost more than the cells.
struct MapBlock {
  static constexpr int kWords = kBlockCells / 64;
  using Mask = std::array<uint64_t, kWords>;

  std::array<float, kBlockCells> logodds;
  std::bitset<kBlockCells> known;
  Mask has_stats{};              ///< bit i: cell i has statistics
  std::vector<CellStats> stats;  ///< of the cells in has_stats, in offset order

  MapBlock() { logodds.fill(0.f); }
  bool hasStats(int i) const { return (has_stats[i >> 6] >> (i & 63)) & 1; }
  /// Position of cell i's statistics in `stats`: how many cells before it have some.
  size_t statsPos(int i) const {
    size_t pos = 0;
    for (int w = 0; w < (i >> 6); ++w) pos += size_t(__builtin_popcountll(has_stats[w]));
    const uint64_t below = (uint64_t(1) << (i & 63)) - 1;
    return pos + size_t(__builtin_popcountll(has_stats[i >> 6] & below));
  }
  const CellStats* statsOf(int i) const { return hasStats(i) ? &stats[statsPos(i)] : nullptr; }
  /// Drops cell i's statistics (it has some); never allocates. Returns whether they were a
  /// Gaussian.
  bool eraseStats(int i);
};

/// Heap bytes of one block's statistics array (NdtMap::memoryBytes() counts them).
inline size_t statsBytes(const std::vector<CellStats>& stats) {
  // glibc's malloc: a chunk header and rounding to 16 bytes for each statistics array.
  constexpr size_t kHeapBlockOverhead = 16;
  return stats.capacity() == 0 ? 0 : stats.capacity() * sizeof(CellStats) + kHeapBlockOverhead;
}

/// A cell's log-odds after an update, kept within the options' bounds (Sec. III-C).
inline float clampLogOdds(double l, const OccupancyOptions& o) {
  return float(std::clamp(l, o.logodds_min, o.logodds_max));
}

}  // namespace ndtom
