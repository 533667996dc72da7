// ndtom-p2d and ndtom-d2d: ndtom::NdtRegistration with its default options (the core's
// defaults are what the benchmark judges) on an NDT-OM of the map scans.
#pragma once

#include "lidar_sequence.h"
#include "ndtom/map/ndt_map.h"
#include "registration_system.h"

namespace ndtom::regbench {

/// The scans `scans` of `sequence` inserted at their reference poses into an NDT-OM of
/// `resolution`, rays cut at `max_range` (default map options otherwise: per-point rays).
NdtMap buildNdtMap(const LidarSequence& sequence, const std::vector<int>& scans, double resolution,
                   double max_range);

class NdtomSystem : public RegistrationSystem {
 public:
  /// `map` must outlive the system. The pyramid is built by the first align() call.
  NdtomSystem(const NdtMap& map, RegistrationMethod method, int threads);

  std::string label() const override;
  std::string settings() const override;
  void setScans(const std::vector<const std::vector<Eigen::Vector3d>*>& scans) override;
  Attempt align(size_t scan, const Eigen::Isometry3d& guess) override;

 private:
  const NdtMap& map_;
  NdtRegistration registration_;
  std::vector<const std::vector<Eigen::Vector3d>*> scans_;  // NdtRegistration's own type
};

}  // namespace ndtom::regbench
