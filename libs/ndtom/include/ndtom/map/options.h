// Options of an NDT-OM map. validate() rejects bad values with a message naming the option.
#pragma once

#include <cstdint>
#include <limits>
#include <string>

#include "ndtom/map/gaussian.h"
#include "ndtom/map/memory_budget.h"

namespace ndtom {

struct StageProfile;  // ndtom/support/stage_profile.h

enum class RayMode {
  /// One ray per point, as in the paper: the reference.
  PerPoint = 0,
  /// One ray per cell hit by the scan, aimed at the mean of the scan's points in that cell
  /// and weighted by their number. Several times fewer voxel visits, approximate N_e.
  PerHitCell = 1,
};

const char* toString(RayMode mode);
/// Accepts "per_point"/"PerPoint"/"0" and "per_hit_cell"/"PerHitCell"/"1"; throws otherwise.
RayMode rayModeFromString(const std::string& text);

/// Occupancy update of Eq. 12.
struct OccupancyOptions {
  bool enabled = true;   ///< false gives the paper's "Recursive NDT" (no rays, no removal)
  double p_hit = 0.6;    ///< p_o: occupancy probability of a cell with hits (Default: 0.6)
  double p_miss = 0.49;  ///< p_e: occupancy probability of a cell a ray crosses (Default: 0.49)
  double logodds_min = -2.0;  ///< lower clamp (Default: -2.0, 50 free rays from 0 at p_e=0.49)
  double logodds_max = 3.5;   ///< upper clamp (Default: 3.5, 88 free rays to empty a cell)

  double hitLogOdds() const;   ///< log(p_o / (1 − p_o))
  double missLogOdds() const;  ///< log(p_e / (1 − p_e))
};

/// Default max_range (m). Finite, as MRPT's own grids (15 m) and unlike OctoMap (no limit):
/// a ray costs its length in cells, so a few points at kilometres (glitches, or a hostile
/// file) would take minutes and gigabytes. 100 m keeps every return of common lidars (the
/// project's lidar scans reach 44 m, the SICK scans of MRPT's SENA log 80 m); a point beyond
/// is noisier than a 0.2 m cell at that range anyway.
inline constexpr double kDefaultMaxRange = 100.0;

/// How one scan is turned into hits and free rays.
struct ScanOptions {
  double min_range = 0.0;  ///< points closer to the sensor are dropped (Default: 0 m)
  /// Farther points give a free ray truncated here and no hit; inf for no limit (Default:
  /// kDefaultMaxRange, 100 m).
  double max_range = kDefaultMaxRange;
  RayMode ray_mode = RayMode::PerPoint;
  /// Threads tracing free rays (Default: 1, at most kMaxThreads). The map does not depend on
  /// it: counts are integers summed over threads. Not stored in map files.
  int threads = 1;
  static constexpr int kMaxThreads = 256;
  /// Bytes the map and one scan's working memory may take; a scan that would need more is
  /// refused with MemoryBudgetError and the map left as it was (Default: a quarter of the
  /// physical memory, at most 512 MB). Like threads, not stored in map files.
  uint64_t memory_budget = defaultMemoryBudget();
  /// Not an option: where to add the time of each insertion stage, or null (Default). Never
  /// compared, copied by copyOptions() or stored; the map does not depend on it.
  StageProfile* profile = nullptr;
};

struct MapOptions {
  double resolution = 0.2;  ///< cell edge (Default: 0.2 m)
  OccupancyOptions occupancy;
  ScanOptions scan;  ///< how NdtMap::insertScan(points, origin) turns scans into updates
  Regularization regularization;  ///< for the covariance handed to users only
};

/// Supported resolution range, so that a map of any real scene fits in memory and index space.
inline constexpr double kMinResolution = 1e-3;  // m
inline constexpr double kMaxResolution = 1e3;   // m

/// Throw std::invalid_argument("<option>: <why>") on the first bad value.
void validate(const OccupancyOptions& o);
void validate(const ScanOptions& o);
void validate(const Regularization& r);
void validate(const MapOptions& o);

}  // namespace ndtom
