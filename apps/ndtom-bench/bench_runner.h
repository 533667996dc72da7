// Times one system over a scan set: the same scans, in the same order, insertion only.
#pragma once

#include "mapping_system.h"
#include "ndtom_apps/progress.h"
#include "run_result.h"

namespace ndtom::bench {

/// Runs `repeats` full replays of `set` into fresh maps of `system`. Per repeat: the peak RSS
/// is reset, the map created, then every scan is prepared (untimed), inserted (timed with a
/// steady clock) and its voxel visits counted (untimed, first repeat only: they repeat).
RunResult runSystem(MappingSystem& system, const ScanSet& set, int repeats,
                    apps::Progress& progress);

}  // namespace ndtom::bench
