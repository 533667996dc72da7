#include "ndtom_apps/settings_from_options.h"

namespace ndtom::mapper {

apps::SourceSettings sourceSettingsFor(const MapperOptions& o, const InsertionOptions& insertion) {
  apps::SourceSettings s;
  s.input = o.input;
  s.format = o.format == apps::InputFormat::Auto ? apps::detectInputFormat(o.input) : o.format;
  s.poses_file = o.poses_file;
  s.pose_format = o.pose_format;
  s.pose_time_tolerance = o.pose_time_tolerance;
  s.camera = o.camera;
  s.decimation = insertion.decimation;
  s.decimation_3d_range = insertion.decimation_3d_range;
  s.max_scans = o.max_scans;
  s.max_scan_points =
      ndtom::NdtMap::maxScanPoints(insertion.toMapOptions().scan.memory_budget);
  return s;
}

OutputSettings outputSettingsFor(const MapperOptions& o, const InsertionOptions& insertion) {
  OutputSettings s;
  s.coarse = o.coarse;
  s.pictures = o.pictures;
  s.image_width = o.image_width;
  s.max_ellipsoids = o.max_ellipsoids;
  s.octomap = o.octomap;
  s.threads = insertion.scan.threads;
  s.tile_blocks = o.tile_blocks;
  return s;
}

}  // namespace ndtom::mapper
