#include "ndtom_apps/scan_source.h"

#include "ndtom_apps/option_values.h"

namespace ndtom::apps {

std::unique_ptr<ScanSource> openScanSource(const SourceSettings& settings) {
  SourceSettings s = settings;
  if (s.format == InputFormat::Auto) s.format = detectInputFormat(s.input);
  switch (s.format) {
    case InputFormat::PcdFolder:
      return openPcdFolder(s);
    case InputFormat::TumRgbd:
      return openTumSequence(s);
    case InputFormat::Rawlog:
      return openRawlog(s);
    case InputFormat::Simplemap:
      return openSimplemap(s);
    case InputFormat::Auto:
      break;
  }
  throw apps::UsageError(s.input + ": unknown input format");
}

std::vector<Eigen::Vector3d> pointsInFrame(const Scan& scan) {
  if (scan.pose_kind == Scan::PoseKind::None) return scan.points_world;
  const Eigen::Isometry3d world_to_frame = scan.frame_pose.inverse();
  std::vector<Eigen::Vector3d> out;
  out.reserve(scan.points_world.size());
  for (const Eigen::Vector3d& p : scan.points_world) out.push_back(world_to_frame * p);
  return out;
}

void placeAt(Scan& scan, const Eigen::Isometry3d& pose) {
  if (scan.place_at) {
    scan.place_at(pose, scan);
  } else {
    const Eigen::Isometry3d frame_to_pose = pose * scan.frame_pose.inverse();
    for (Eigen::Vector3d& p : scan.points_world) p = frame_to_pose * p;
    scan.sensor_origin = frame_to_pose * scan.sensor_origin;
  }
  scan.frame_pose = pose;
}

}  // namespace ndtom::apps
