// What every stage of one scan's insertion reads: the grid, the insertion options, the sensor
// origin and the threads. Private to the library.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cstddef>

#include "ndtom/map/cell_index.h"
#include "ndtom/map/options.h"
#include "support/parallel.h"

namespace ndtom {

// A stage runs on fewer threads when it has little work: starting a thread costs more than a
// small stage's work.
inline constexpr size_t kMinPointsPerThread = 8192;
inline constexpr size_t kMinRaysPerThread = 256;
inline constexpr size_t kMinGroupsPerThread = 2048;
inline constexpr size_t kMinBlocksPerThread = 32;

struct ScanContext {
  const GridGeometry& geometry;
  const ScanOptions& options;
  Eigen::Vector3d origin;  ///< the sensor, world frame
  WorkerPool& pool;

  /// Threads for `items` of work, at least `min_items_per_thread` each, at most the options'.
  size_t threadsFor(size_t items, size_t min_items_per_thread) const {
    return ndtom::threadsFor(items, min_items_per_thread, size_t(options.threads));
  }
};

}  // namespace ndtom
