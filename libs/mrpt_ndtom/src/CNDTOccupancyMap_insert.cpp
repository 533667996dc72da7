// CNDTOccupancyMap: inserting observations (paper Sec. III, run by the core).
#include "mrpt_ndtom/CNDTOccupancyMap.h"

namespace mrpt_ndtom {

ndtom::InsertionReport CNDTOccupancyMap::insertPoints(
    const std::vector<Eigen::Vector3d>& points_world, const Eigen::Vector3d& sensor_origin) {
  applyInsertionOptions();
  // threads and the memory budget do not change the map: taken from insertionOptions at
  // each scan (validated by applyInsertionOptions), not by rebuilding the map.
  const ndtom::ScanOptions insert = insertionOptions.toMapOptions().scan;
  ndtom::InsertionReport report;
  try {
    report = m_map.insertScan(points_world, sensor_origin, insert);
  } catch (const std::exception& e) {  // a bad origin, the memory budget; the map unchanged
    THROW_EXCEPTION(std::string("CNDTOccupancyMap: ") + e.what());
  }
  if (report.pointsUsed() > 0) {
    invalidateLookup();
    m_last_report = report;
  }
  MRPT_LOG_DEBUG_STREAM("insertion: " << report.toString());
  if (report.rejected() > 0 && report.pointsUsed() == 0)
    MRPT_LOG_WARN_STREAM("all " << report.points_in
                                << " points were rejected; map unchanged: " << report.toString());
  return report;
}

bool CNDTOccupancyMap::internal_insertObservation(
    const mrpt::obs::CObservation& obs,
    const std::optional<const mrpt::poses::CPose3D>& robotPose) {
  const auto extracted = observationPoints(obs, robotPose.value_or(mrpt::poses::CPose3D()),
                                           insertionOptions.extractionOptions());
  if (!extracted) return false;  // not a type this map understands
  if (extracted->points_world.empty()) {
    MRPT_LOG_DEBUG_STREAM("insertion: " << obs.GetRuntimeClass()->className
                                        << " without valid points; map unchanged");
    return false;
  }
  return insertPoints(extracted->points_world, extracted->sensor_origin).pointsUsed() > 0;
}

}  // namespace mrpt_ndtom
