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

/// Insertion seconds of two systems replayed side by side (see runPaired), summed over scans.
struct PairedSeconds {
  double first = 0, second = 0;
};

/// Scans per turn in runPaired: short enough that a spell of load on a shared machine falls
/// on both systems, long enough that each turn but its first scan finds its own map in cache.
inline constexpr size_t kScansPerTurn = 4;

/// Replays for a side-by-side comparison: at least `min_repeats`, and enough that the faster
/// system's side lasts `min_seconds` when one of its replays takes `replay_seconds`. On a
/// shared machine a sub-second measurement is decided by whichever spell of load meets it.
int pairedRepeats(double replay_seconds, int min_repeats, double min_seconds);

/// Replays `set` `repeats` times into fresh maps of `first` and `second`, which take turns of
/// kScansPerTurn scans (first, second, first, ...): each still sees every scan once per
/// repeat, in order. The way to measure one's speed-up over the other on a
/// shared machine, where runs one after the other can meet different loads.
PairedSeconds runPaired(MappingSystem& first, MappingSystem& second, const ScanSet& set,
                        int repeats, apps::Progress& progress);

}  // namespace ndtom::bench
