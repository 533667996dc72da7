// Tracking that does not stop where the prior map ends: the scans localized so far, inserted
// at their poses into a map of their own beside the prior one (same options). Scans are
// registered against the prior map's region around the robot with the live map's cells added
// where the prior map has none, or has no Gaussian where the live map has one: where both
// hold a Gaussian the prior's wins, so when the prior map comes back into view the scans
// re-anchor to it. The prior map is never changed.
#pragma once

#include <Eigen/Geometry>
#include <cstdint>
#include <optional>
#include <vector>

#include "ndtom/map/ndt_map.h"
#include "ndtom/online/region_refresh.h"

namespace ndtom::localizer {

struct LiveMapSettings {
  bool enabled = true;
  /// Keep the blocks the live map drops behind the robot, for extended() (--save-map).
  bool keep_all = false;
  double radius = 50;  ///< m: the target's region around the robot, and what the live map keeps
  ndtom::RegionRefresh refresh;  ///< when the target is cut again (2 m, 10°, 10 scans)
};

class LiveMap {
 public:
  LiveMap(const ndtom::MapOptions& options, const LiveMapSettings& settings);

  /// What to register against around `sensor`: the prior map's region with the live map's
  /// cells the prior lacks (above); the same object until the policy cuts a new one.
  const ndtom::NdtMap& targetAround(const ndtom::NdtMap& prior, const Eigen::Isometry3d& sensor);
  /// A placed scan, points in the map frame. Blocks farther than the radius from the sensor
  /// (x, y) are dropped, so the live map stays a region. Throws like NdtMap::insertScan.
  void insert(const std::vector<Eigen::Vector3d>& points, const Eigen::Vector3d& sensor_origin);

  /// Where the scan's points (map frame, at its pose) land: the fraction in cells with a
  /// Gaussian of the prior map, and of the live map only.
  struct Shares {
    double prior = 0, live = 0;
  };
  Shares sharesOf(const ndtom::NdtMap& prior, const std::vector<Eigen::Vector3d>& points) const;

  const ndtom::NdtMap& map() const { return live_; }
  /// The prior map extended by every live cell it does not know (for --save-map).
  ndtom::NdtMap extended(const ndtom::NdtMap& prior) const;

 private:
  LiveMapSettings settings_;
  ndtom::NdtMap live_;
  ndtom::NdtMap dropped_;  ///< what left live_, if kept (the first version of each cell)
  ndtom::NdtMap target_;
  uint64_t target_prior_revision_ = 0, target_live_revision_ = 0;
  std::optional<Eigen::Isometry3d> cut_at_;
  int scans_since_cut_ = 0;
};

}  // namespace ndtom::localizer
