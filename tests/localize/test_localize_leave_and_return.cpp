// ndtom-localize on a drive that leaves its prior map for 40 scans and comes back: the prior
// map (of an earlier drive, 20 m around each of its scans) has an 80 m gap along the route.
// With the live map every scan is placed: by the live map in the middle of the gap (where
// the scans drift by decimetres at most) and by the prior map again after it, where the error
// is back to centimetres. Without the live map most scans in the gap are lost or placed metres
// off (doc/localization.md).
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include "city_drive.h"
#include "mapper/mapper_run.h"
#include "ndtom/files/map_io.h"
#include "support/program_run.h"

using namespace mapper_test;

namespace {


TEST(LocalizeLeaveAndReturn, TheLiveMapCarriesTheDriveThroughAGapInThePriorMap) {
  TempDir dir;
  ndtom::world::CityLayout layout;
  layout.blocks_x = layout.blocks_y = 3;
  const ndtom::world::CityWorld city(layout);
  ndtom::world::LidarModel lidar;
  lidar.azimuth_steps = 450;
  lidar.max_range = 30;
  const double gap_from = 60, gap_to = 140;  // along the route (m): no map scan between

  // The prior map: a drive with a scan every 3 m, none in the gap, 20 m around each scan.
  ndtom::world::RouteSettings route;
  route.length = 200;
  route.step = 3;
  ndtom::MapOptions options;
  options.resolution = 0.2;
  options.scan.max_range = 20;
  ndtom::NdtMap map(options);
  city_drive::insertDrive(map, city, lidar, ndtom::world::driveThrough(city, route), [&](size_t i) {
    const double along = route.step * double(i);
    return !(along > gap_from && along < gap_to);
  });
  const std::string map_file = (dir / "prior.ndtom").string();
  ndtom::saveMap(map, map_file);

  // The drive: the same streets, a scan every 2 m (between the map's), other noise; default
  // options.
  route.step = 2;
  lidar.seed = 2;
  const auto poses = ndtom::world::driveThrough(city, route);
  city_drive::writeDrive(city, lidar, poses, dir / "drive");
  const std::string out = (dir / "loc").string();
  const ProgramRun run = runExecutable(
      NDTOM_LOCALIZE_EXE, quoted(map_file) + " " + quoted((dir / "drive").string()) +
                              " --initial '" + city_drive::initialPose(poses[0]) +
                              "' --no-pictures -q -o " + quoted(out),
      dir);
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const ndtom::testing::Csv scans = ndtom::testing::readCsv(out + ".scans.csv");
  ASSERT_EQ(scans.rows.size(), poses.size());
  size_t live_only = 0, after_gap = 0, prior_after_gap = 0;
  for (size_t i = 0; i < poses.size(); ++i) {
    ASSERT_NE(scans.text(i, "outcome"), "lost") << "scan " << i;
    const double along = route.step * double(i);
    const bool in_prior_view = along < gap_from || along > gap_to + 20;
    EXPECT_LT(scans.number(i, "error_m"), in_prior_view ? 0.15 : 0.6) << "scan " << i;
    EXPECT_LT(scans.number(i, "error_deg"), 1.0) << "scan " << i;
    live_only += scans.text(i, "placed_in") == "live";
    if (along > gap_to + 20) {
      ++after_gap;
      prior_after_gap += scans.text(i, "placed_in") == "prior";
    }
  }
  EXPECT_GE(live_only, 10u);  // the middle of the gap: the live map alone
  EXPECT_GE(prior_after_gap, after_gap * 3 / 4);  // back on the prior map
  // Re-anchored: the last scans are as close as those before the gap.
  const double last = scans.number(poses.size() - 1, "error_m");
  EXPECT_LT(last, 0.1);
}

}  // namespace
