// Online NDT-OM through MRPT's types (ndtom::OnlineMapper's face in the MRPT layer): each
// observation is registered against the map built so far and inserted at the pose found, so
// a log is mapped without poses from elsewhere; odometry, where there is some, only improves
// the prediction. Observations of the types CNDTOccupancyMap inserts (2D/3D range scans,
// point clouds, Velodyne scans), their sensor pose on the robot applied.
#pragma once

#include <mrpt/obs/CObservation.h>
#include <mrpt/poses/CPose3D.h>
#include <mrpt/poses/CPose3DPDFGaussian.h>

#include <optional>

#include "mrpt_ndtom/CNDTOccupancyMap.h"
#include "ndtom/online/online_mapper.h"

namespace mrpt_ndtom {

class CNDTOnlineMapper {
 public:
  /// The map's options as CNDTOccupancyMap takes them (resolution, occupancy, decimation,
  /// ...), the registration's and recovery's as the core takes them (its `map` is replaced by
  /// `map_options`). The first observation is placed at `first_pose` (the robot's). Throws
  /// std::invalid_argument naming a bad option.
  explicit CNDTOnlineMapper(const CNDTOccupancyMap::TInsertionOptions& map_options = {},
                            const ndtom::OnlineMapperOptions& online = {},
                            const mrpt::poses::CPose3D& first_pose = {});

  /// The robot's pose when `obs` was taken, with its covariance (MRPT's x, y, z, yaw, pitch,
  /// roll), and the observation inserted there unless nothing placed it (lastStep().outcome
  /// is then Lost and the pose is the prediction). `odometry`: the robot's motion since the
  /// previous observation. Throws std::invalid_argument for an unsupported observation type,
  /// time going backwards, or what insertion refuses (the map unchanged).
  mrpt::poses::CPose3DPDFGaussian processObservation(
      const mrpt::obs::CObservation& obs,
      const std::optional<mrpt::poses::CPose3D>& odometry = std::nullopt);

  /// Inserts `obs` at a pose known from elsewhere (a map built before), which becomes the
  /// last pose: the next observation is registered from there. Throws as processObservation.
  void insertAtPose(const mrpt::obs::CObservation& obs, const mrpt::poses::CPose3D& robot_pose);

  /// The figures of the last observation: outcome, registration verdict, timing.
  const ndtom::OnlineStep& lastStep() const { return m_last; }
  const ndtom::NdtMap& ndtMap() const { return m_mapper.map(); }
  /// The map so far as MRPT's map object (a copy: the mapper goes on).
  CNDTOccupancyMap::Ptr map() const;

 private:
  struct Located;
  Located locate(const mrpt::obs::CObservation& obs,
                 const std::optional<mrpt::poses::CPose3D>& odometry);
  void commit(Located& located);

  CNDTOccupancyMap::TInsertionOptions m_insertion;
  ndtom::OnlineMapper m_mapper;
  ndtom::OnlineStep m_last;
  size_t m_observations = 0;
};

}  // namespace mrpt_ndtom
