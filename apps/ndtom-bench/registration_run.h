// Scan-to-map registration timed like the insertions: the scans of a dataset registered
// against the map built from them, each from its pose moved off by a fixed amount.
#pragma once

#include <string>
#include <vector>

#include "ndtom/map/ndt_map.h"
#include "ndtom_apps/progress.h"
#include "run_result.h"
#include "scan_set.h"

namespace ndtom::bench {

/// The guess: each scan's pose moved 0.3 m and turned 3° about z (issue 37's tracking case).
Eigen::Isometry3d offsetGuess(const Eigen::Isometry3d& pose);

/// Registers the first `scans` scans of `set` (P2D, default options, `threads` threads)
/// against `map`, timing each align() and its process CPU time, with a stage profile. The
/// pyramid is built by one untimed call first: the runs time tracking, not the first look at
/// a map. The poses found go to `poses`. Label "registration-p2d/t<threads>". That call's
/// pyramid stage goes to `pyramid` (label "pyramid/t<threads>", one call, no CPU time).
RunResult runRegistration(const NdtMap& map, const ScanSet& set, size_t scans, int threads,
                          apps::Progress& progress, std::vector<Eigen::Isometry3d>& poses,
                          RunResult& pyramid);

}  // namespace ndtom::bench
