// NDT-OM under test: NdtMap::insertScan with the chosen ray mode and thread count.
#pragma once

#include <memory>
#include <type_traits>
#include <utility>

#include "mapping_system.h"
#include "ndtom/map/ndt_map.h"

namespace ndtom::bench {

/// True when the core's ScanOptions has the `threads` field (multi-threaded insertion).
/// Detected at compile time so the harness builds against the core before and after it.
template <class T, class = void>
struct HasThreadsField : std::false_type {};
template <class T>
struct HasThreadsField<T, std::void_t<decltype(std::declval<T&>().threads = 1)>> : std::true_type {
};
inline constexpr bool kCoreHasThreads = HasThreadsField<ScanOptions>::value;

class NdtomSystem : public MappingSystem {
 public:
  NdtomSystem(const NdtomSystem&) = delete;
  NdtomSystem& operator=(const NdtomSystem&) = delete;
  /// Throws std::invalid_argument if threads > 1 and the core has no threaded insertion.
  NdtomSystem(double resolution, double max_range, RayMode mode, int threads);

  std::string label() const override;
  void reset() override;
  void insertScan(const Scan& scan) override;
  uint64_t lastScanVisits(const Scan&) override { return last_report_.voxel_visits; }
  MapSize mapSize() const override;
  const StageProfile* stageProfile() const override { return &profile_; }

  const NdtMap& map() const { return *map_; }
  RayMode rayMode() const { return options_.scan.ray_mode; }
  int threads() const { return threads_; }
  /// Hands the map over (the runner keeps reference maps for comparisons).
  std::unique_ptr<NdtMap> releaseMap() { return std::move(map_); }

 private:
  StageProfile profile_;  // options_.scan.profile points to it
  MapOptions options_;
  int threads_;
  std::unique_ptr<NdtMap> map_;
  InsertionReport last_report_;
};

}  // namespace ndtom::bench
