// The localization loop: every scan of a source registered in the map. Each scan starts from
// a prediction (the log's odometry where it has some, else constant velocity) and is placed
// near it (ndtom::ScanPlacer: retries from the last pose, then a search around the
// prediction); a scan none of that places is lost. Without an initial pose, and after a run of lost scans
// if asked, the scan is searched for in the whole map (global localization).
#pragma once

#include <Eigen/Geometry>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "live_map.h"
#include "ndtom/localization/scan_placer.h"
#include "ndtom/registration/registration.h"
#include "ndtom_apps/progress.h"
#include "ndtom_apps/scan_source.h"

namespace ndtom::localizer {

struct TrackingSettings {
  /// Registration, retries, the search around the prediction (4 m, ±60°), the rules against
  /// sliding; its search grid serves the whole-map search too.
  ndtom::PlacementOptions placement;
  std::optional<Eigen::Isometry3d> initial;  ///< none: global localization of the first scan
  int relocalize_after = 0;       ///< lost scans in a row before a global search; 0: never
  bool global_every_scan = false;  ///< no tracking: every scan searched for in the whole map
  /// Called before each scan is localized with where the robot is predicted to be, or with
  /// nothing before a search of the whole map: a map held in part (RegionMap) loads there.
  std::function<void(const std::optional<Eigen::Vector3d>& around)> prepare_map;
  LiveMapSettings live;  ///< the map of the localized scans beside the prior map
};

/// How a scan's pose was found.
enum class Outcome { Tracked, Recovered, Relocalized, Lost };
const char* toString(Outcome outcome);

struct ScanRecord {
  size_t index = 0;
  std::string name;
  double time = 0;
  size_t points = 0;  ///< read (after decimation)
  Outcome outcome = Outcome::Lost;
  /// What found the pose: "prediction", "last pose", "local search", "global search" or "".
  std::string found_by;
  int registrations = 0;  ///< runs of the registration (a search counts its refinements)
  int weak_directions = 0;  ///< translation directions that kept the prediction
  std::optional<Eigen::Isometry3d> prediction;  ///< none before the first pose is known
  ndtom::RegistrationResult result;             ///< of the registration that decided
  /// The pose kept: the registration's if it converged, else the prediction (if any).
  std::optional<Eigen::Isometry3d> pose;
  std::optional<Eigen::Isometry3d> reference;  ///< from the input or --reference
  /// Of the scan's points at the kept pose: the fraction in cells with a Gaussian of the
  /// prior map, and of the live map only (which map placed it).
  double in_prior = 0, in_live = 0;
  double seconds = 0;                          ///< localizing this scan (reading excluded)
  size_t map_bytes = 0;                        ///< the map's memory after it (resident part)
  size_t rss_bytes = 0;                        ///< the process's resident memory after it
};

struct TrackingResult {
  std::vector<ScanRecord> scans;
  double seconds = 0;  ///< wall time of the whole loop (reading included)
  size_t count(Outcome outcome) const;
  size_t localized() const { return scans.size() - count(Outcome::Lost); }
  bool odometry_used = false;
  size_t global_searches = 0;
  /// The prior map extended by the live map's cells (only when live.keep_all).
  std::optional<ndtom::NdtMap> extended_map;
};

/// Which map(s) placed a scan: "prior", "live" or "prior+live" (by where its points land).
const char* placedIn(const ScanRecord& record);

/// A pose for a scan from elsewhere (a --reference trajectory), by scan index and time.
using ReferenceLookup =
    std::function<std::optional<Eigen::Isometry3d>(size_t index, double time)>;

/// Localizes every scan of `source` in `map` (`already_read` of them were taken before: left
/// out, as --skip does). The reference is `reference` if given (not empty), else the input's
/// own trajectory where it is one (Scan::PoseKind::Reference). Throws
/// apps::InputError for unreadable data.
TrackingResult track(const ndtom::NdtMap& map, apps::ScanSource& source,
                     const TrackingSettings& settings, const ReferenceLookup& reference,
                     apps::Progress& progress, size_t already_read = 0);

}  // namespace ndtom::localizer
