#include "ndtom_system.h"

#include <stdexcept>

namespace ndtom::bench {

namespace {

template <class Options>
void setThreads(Options& o, int threads) {
  if constexpr (HasThreadsField<Options>::value) {
    o.threads = threads;
  } else if (threads != 1) {
    throw std::invalid_argument("--threads " + std::to_string(threads) +
                                ": this core has no multi-threaded insertion "
                                "(ScanOptions::threads)");
  }
}

}  // namespace

NdtomSystem::NdtomSystem(double resolution, double max_range, RayMode mode, int threads)
    : threads_(threads) {
  options_.resolution = resolution;
  options_.scan.max_range = max_range;
  options_.scan.ray_mode = mode;
  setThreads(options_.scan, threads);
  options_.scan.profile = &profile_;  // a few clock reads a stage: lost in a scan's time
  validate(options_);
}

std::string NdtomSystem::label() const {
  const char* mode = rayMode() == RayMode::PerPoint ? "ndtom-point" : "ndtom-hitcell";
  return std::string(mode) + "/t" + std::to_string(threads_);
}

void NdtomSystem::reset() {
  map_.reset();  // free the old map first: peak memory must not count two maps
  map_ = std::make_unique<NdtMap>(options_);
}

void NdtomSystem::insertScan(const Scan& scan) {
  last_report_ = map_->insertScan(scan.points, scan.origin);
}

MapSize NdtomSystem::mapSize() const {
  return {map_->numCells(), map_->memoryBytes()};
}

}  // namespace ndtom::bench
