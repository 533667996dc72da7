// mrpt-icp: MRPT's point-to-point ICP (mrpt::slam::CICP::Align3D, MRPT 2.5.8) with a
// CSimplePointsMap of the map scans, decimated to one point per 0.1 m cube, as the reference.
#pragma once

#include <memory>

#include "lidar_sequence.h"
#include "registration_system.h"

namespace mrpt::maps {
class CSimplePointsMap;
}

namespace ndtom::regbench {

/// CICP's options that the benchmark sets (the rest keep MRPT's defaults), and the map's
/// decimation.
struct MrptIcpSettings {
  double map_leaf = 0.1;  ///< m: one point (the centroid) per cube of the map's points
  /// Correspondences closer than threshold_dist + threshold_ang·range: from the start, a
  /// turn of the guess's angle moves a point at range r by about r·angle.
  double threshold_dist = 1.0;            ///< m
  double threshold_ang_degrees = 3.0;     ///< per metre of range from the sensor
  double alfa = 0.5;                      ///< both thresholds shrink by this when a step stalls
  double smallest_threshold_dist = 0.05;  ///< m: the thresholds shrink down to this
  unsigned max_iterations = 100;
  /// Every 20th scan point looks for its correspondence (a different 20th after each
  /// annealing step): 12/12 up to 1 m / 10° as with every 5th, 4 times faster.
  unsigned decimation = 20;
};

/// "MRPT 2.5.8": the version this program was built with.
std::string mrptVersion();

class MrptIcpSystem : public RegistrationSystem {
 public:
  MrptIcpSystem(const MapScans& map, const MrptIcpSettings& settings = {});
  ~MrptIcpSystem() override;

  std::string label() const override { return "mrpt-icp"; }
  std::string settings() const override;
  void setScans(const std::vector<const std::vector<Eigen::Vector3d>*>& scans) override;
  Attempt align(size_t scan, const Eigen::Isometry3d& guess) override;

  size_t mapPoints() const;

 private:
  MrptIcpSettings settings_;
  std::unique_ptr<mrpt::maps::CSimplePointsMap> map_;
  std::vector<std::unique_ptr<mrpt::maps::CSimplePointsMap>> scans_;
};

}  // namespace ndtom::regbench
