#include "mrpt_ndtom/CNDTOnlineMapper.h"

#include <mrpt/system/datetime.h>

#include <stdexcept>

#include "mrpt_ndtom/CNDTRegistration.h"
#include "mrpt_ndtom/observation_points.h"

namespace mrpt_ndtom {
namespace {

ndtom::OnlineMapperOptions withMap(ndtom::OnlineMapperOptions online,
                                   const CNDTOccupancyMap::TInsertionOptions& map) {
  online.map = map.toMapOptions();
  return online;
}

mrpt::poses::CPose3D toCPose3D(const Eigen::Isometry3d& pose) {
  return mrpt::poses::CPose3D(mrpt::math::CMatrixDouble44(pose.matrix()));
}

}  // namespace

CNDTOnlineMapper::CNDTOnlineMapper(const CNDTOccupancyMap::TInsertionOptions& map_options,
                                   const ndtom::OnlineMapperOptions& online,
                                   const mrpt::poses::CPose3D& first_pose)
    : m_insertion(map_options), m_mapper(withMap(online, map_options), toIsometry(first_pose)) {}

// A step of the core's mapper with the observation's points (robot frame) it was found for.
struct CNDTOnlineMapper::Located {
  ObservationPoints points;
  ndtom::OnlineStep step;
};

CNDTOnlineMapper::Located CNDTOnlineMapper::locate(
    const mrpt::obs::CObservation& obs, const std::optional<mrpt::poses::CPose3D>& odometry) {
  // The points in the robot's frame; time from the observation, else its order.
  auto points = observationPoints(obs, mrpt::poses::CPose3D(), m_insertion.extractionOptions());
  if (!points)
    throw std::invalid_argument(std::string("CNDTOnlineMapper: unsupported observation type ") +
                                obs.GetRuntimeClass()->className);
  const double time = obs.timestamp == INVALID_TIMESTAMP ? double(m_observations)
                                                         : mrpt::Clock::toDouble(obs.timestamp);
  std::optional<Eigen::Isometry3d> motion;
  if (odometry) motion = toIsometry(*odometry);
  ndtom::OnlineStep step = m_mapper.locate(points->points_world, time, motion);
  return {std::move(*points), std::move(step)};
}

void CNDTOnlineMapper::commit(Located& located) {
  ndtom::OnlineStep& step = located.step;
  std::vector<Eigen::Vector3d> in_map;
  in_map.reserve(located.points.points_world.size());
  for (const Eigen::Vector3d& p : located.points.points_world) in_map.push_back(step.pose * p);
  m_mapper.commit(step, in_map, step.pose * located.points.sensor_origin);
  m_last = step;
  ++m_observations;
}

mrpt::poses::CPose3DPDFGaussian CNDTOnlineMapper::processObservation(
    const mrpt::obs::CObservation& obs, const std::optional<mrpt::poses::CPose3D>& odometry) {
  Located located = locate(obs, odometry);
  commit(located);
  const mrpt::poses::CPose3D pose = toCPose3D(m_last.pose);
  return mrpt::poses::CPose3DPDFGaussian(
      pose, toMrptPoseCovariance(m_last.registration.covariance, pose));
}

void CNDTOnlineMapper::insertAtPose(const mrpt::obs::CObservation& obs,
                                    const mrpt::poses::CPose3D& robot_pose) {
  Located located = locate(obs, std::nullopt);
  // The given pose replaces what registration found; First is the outcome of a scan placed
  // without registration, which commit() inserts.
  located.step.pose = toIsometry(robot_pose);
  located.step.outcome = ndtom::OnlineOutcome::First;
  located.step.found_by = "given pose";
  commit(located);
}

CNDTOccupancyMap::Ptr CNDTOnlineMapper::map() const {
  auto out = CNDTOccupancyMap::Create(m_insertion.resolution);
  out->insertionOptions = m_insertion;
  out->setNdtMap(m_mapper.map());
  return out;
}

}  // namespace mrpt_ndtom
