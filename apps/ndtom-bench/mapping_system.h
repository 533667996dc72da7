// One mapping system under test, behind the same small interface, so the runner times all of
// them the same way: reset() and the statistics are untimed, insertScan() is the timed region.
#pragma once

#include <cstdint>
#include <string>

#include "ndtom/support/stage_profile.h"
#include "scan_set.h"

namespace ndtom::bench {

/// Size of a finished map, in each system's own accounting.
struct MapSize {
  size_t cells = 0;         ///< NDT-OM: known cells; OctoMap: leaves; grid: cells ≠ prior
  size_t memory_bytes = 0;  ///< NDT-OM: memoryBytes(); OctoMap: memoryUsage(); grid: the array
};

class MappingSystem {
 public:
  virtual ~MappingSystem() = default;

  /// Label in tables, e.g. "ndtom-point/t1".
  virtual std::string label() const = 0;
  /// Drops any previous map and starts an empty one (untimed).
  virtual void reset() = 0;
  /// Untimed: converts the scan to the system's own input type, if it has one.
  virtual void prepareScan(const Scan&) {}
  /// The timed region: inserts one (prepared) scan, nothing else.
  virtual void insertScan(const Scan& scan) = 0;
  /// Free-space voxels the last insertScan's rays visited, end cells excluded (reported by
  /// the system or reconstructed untimed, see each system).
  virtual uint64_t lastScanVisits(const Scan& scan) = 0;
  virtual MapSize mapSize() const = 0;
  /// Where the timed calls' time went, stage by stage, since the system was made; null for
  /// systems that do not say.
  virtual const StageProfile* stageProfile() const { return nullptr; }
};

}  // namespace ndtom::bench
