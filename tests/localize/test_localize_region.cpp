// ndtom-localize in a tiled map held in part: a drive through the procedural city localized
// in a map of an earlier drive, with only the tiles within 35 m of the robot resident (the
// sensor sees 30 m). Every scan is placed where the whole map places it; tiles are loaded
// ahead and dropped behind, and the resident map stays a fraction of the whole.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <iomanip>

#include "city_drive.h"
#include "mapper/mapper_run.h"
#include "ndtom/files/map_io.h"
#include "ndtom/files/tiled_map_io.h"
#include "support/program_run.h"

using namespace mapper_test;

namespace {

using city_drive::writeDrive;

TEST(LocalizeRegion, TiledMapLoadedAroundTheRobotPlacesEveryScan) {
  TempDir dir;
  ndtom::world::CityLayout layout;
  layout.blocks_x = layout.blocks_y = 3;
  const ndtom::world::CityWorld city(layout);
  ndtom::world::LidarModel lidar;
  lidar.rings = 32;
  lidar.azimuth_steps = 360;
  lidar.max_range = 30;  // the region's radius must cover what the sensor sees

  // The map: a first drive, a scan every 2 m, in memory, saved in tiles of 12.8 m.
  ndtom::world::RouteSettings route;
  route.length = 180;
  route.step = 2;
  ndtom::MapOptions options;
  options.resolution = 0.4;
  ndtom::NdtMap map(options);
  city_drive::insertDrive(map, city, lidar, ndtom::world::driveThrough(city, route));
  const std::string tiles = (dir / "city.ndtomtiles").string();
  ndtom::saveTiledMap(map, tiles, 4);
  ndtom::saveMap(map, (dir / "whole.ndtom").string());

  // The drive to localize: the same streets, scans between the map's, other noise.
  route.step = 3;  // the first step, with no motion known yet, is within the local search
  lidar.seed = 2;
  const auto poses = ndtom::world::driveThrough(city, route);
  writeDrive(city, lidar, poses, dir / "drive");
  const std::string initial = city_drive::initialPose(poses[0]);
  const std::string prefix = (dir / "loc").string();
  const auto localize = [&](const std::string& map_file, const std::string& out,
                            const std::string& extra) {
    const ProgramRun run = runExecutable(
        NDTOM_LOCALIZE_EXE,
        quoted(map_file) + " " + quoted((dir / "drive").string()) + " --initial '" +
            initial + "' --decimation 2 -q -o " + quoted(out) + " " + extra,
        dir);
    EXPECT_EQ(run.exit_code, 0) << run.err;
  };
  localize(tiles, prefix, "--region-radius 35");
  // The same drive in the whole map: the second method the region must agree with.
  localize((dir / "whole.ndtom").string(), (dir / "whole").string(), "--no-pictures");
  const std::string json = readText(prefix + ".summary.json");
  EXPECT_EQ(jsonNumber(json, "scans"), double(poses.size()));
  EXPECT_EQ(jsonNumber(json, "lost"), 0);
  // Every scan placed as in the whole map, within 5 cm; nearly all within 10 cm of the
  // reference (a flat ground's lidar rings can pull a scan onto a map scan's position).
  const ndtom::testing::Csv in_region = ndtom::testing::readCsv(prefix + ".scans.csv"),
                            in_whole = ndtom::testing::readCsv((dir / "whole.scans.csv").string());
  ASSERT_EQ(in_region.rows.size(), in_whole.rows.size());
  size_t close = 0;
  for (size_t i = 0; i < in_region.rows.size(); ++i) {
    Eigen::Vector3d a, b;
    for (int k = 0; k < 3; ++k) {
      a[k] = in_region.number(i, std::string(1, char('x' + k)));
      b[k] = in_whole.number(i, std::string(1, char('x' + k)));
    }
    EXPECT_LT((a - b).norm(), 0.05) << "scan " << i;
    close += in_region.number(i, "error_m") < 0.1;
  }
  EXPECT_GE(double(close), 0.95 * double(poses.size()));
  const double in_file = jsonNumber(json, "tiles_in_file");
  EXPECT_GT(jsonNumber(json, "loads"), jsonNumber(json, "max_resident_tiles"));  // loaded ahead
  EXPECT_GT(jsonNumber(json, "drops"), 0);                                        // dropped behind
  EXPECT_LT(jsonNumber(json, "max_resident_tiles"), 0.6 * in_file);
  ASSERT_EQ(in_region.rows.size(), poses.size());
  double largest = 0;
  for (size_t i = 0; i < in_region.rows.size(); ++i)
    largest = std::max(largest, in_region.number(i, "map_bytes"));
  EXPECT_LT(largest, 0.75 * double(map.memoryBytes()));
  EXPECT_GT(largest, 0);
  EXPECT_TRUE(fs::exists(prefix + ".top.png"));
}

}  // namespace
