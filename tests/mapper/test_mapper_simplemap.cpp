// The lidar scans given as an MRPT simplemap (written here through MRPT: one keyframe per
// scan at its known pose, holding a CObservationPointCloud or a CObservation3DRangeScan with
// the scan's points) must give the same map, byte for byte, as the PCD folder + poses.txt.
#include <mrpt/io/CFileOutputStream.h>
#include <mrpt/maps/CSimpleMap.h>
#include <mrpt/maps/CSimplePointsMap.h>
#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/obs/CObservationPointCloud.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/poses/CPose3DPDFGaussian.h>
#include <mrpt/serialization/CArchive.h>

#include "mapper_run.h"
#include "ndtom_io/pcd_reader.h"
#include "ndtom_io/pose_file.h"

using namespace mapper_test;

namespace {

enum class Keyframes { PointClouds, RangeScans };

mrpt::obs::CObservation::Ptr observationOf(const std::vector<Eigen::Vector3d>& points,
                                           Keyframes kind) {
  if (kind == Keyframes::PointClouds) {
    auto cloud = mrpt::maps::CSimplePointsMap::Create();
    for (const auto& p : points) cloud->insertPoint(float(p.x()), float(p.y()), float(p.z()));
    auto obs = mrpt::obs::CObservationPointCloud::Create();
    obs->pointcloud = cloud;
    return obs;
  }
  auto obs = mrpt::obs::CObservation3DRangeScan::Create();
  obs->hasPoints3D = true;
  obs->resizePoints3DVectors(points.size());
  for (size_t i = 0; i < points.size(); ++i) {
    obs->points3D_x[i] = float(points[i].x());
    obs->points3D_y[i] = float(points[i].y());
    obs->points3D_z[i] = float(points[i].z());
  }
  return obs;
}

// The shipped scans as keyframes; the sensor is at the robot's origin (identity sensor pose).
mrpt::maps::CSimpleMap lidarSimplemap(Keyframes kind) {
  const auto poses = ndtom::io::readPoseFile(kLidar + "/poses.txt");
  mrpt::maps::CSimpleMap map;
  for (size_t i = 0; i < poses.size(); ++i) {
    const auto cloud = ndtom::io::readPcd(kLidar + "/full" + std::to_string(i) + ".pcd");
    auto frame = mrpt::obs::CSensoryFrame::Create();
    frame->insert(observationOf(cloud.points, kind));
    const mrpt::poses::CPose3D pose(mrpt::math::CMatrixDouble44(poses[i].pose.matrix()));
    map.insert(mrpt::poses::CPose3DPDFGaussian::Create(pose), frame);
  }
  return map;
}

// The first 4 scans at 0.4 m: enough to compare, quick to build.
std::string mapOf(const std::string& input, const TempDir& dir, const std::string& stem) {
  const ProgramRun run = runMapper(quoted(input) + " -o " + quoted((dir / stem).string()) +
                                       " --no-pictures --max-scans 4 --resolution 0.4",
                                   dir);
  EXPECT_EQ(run.exit_code, 0) << run.err;
  return readText(dir / (stem + ".ndtom"));
}

}  // namespace

TEST(MapperSimplemap, PointCloudKeyframesGiveThePcdFolderMap) {
  TempDir dir;
  // Gzip-compressed, as MRPT writes .simplemap.gz, and plain.
  const auto simplemap = lidarSimplemap(Keyframes::PointClouds);
  ASSERT_TRUE(simplemap.saveToFile((dir / "scans.simplemap.gz").string()));
  {
    mrpt::io::CFileOutputStream file((dir / "scans.simplemap").string());
    auto archive = mrpt::serialization::archiveFrom(file);
    archive << simplemap;
  }
  const std::string expected = mapOf(kLidar, dir, "pcd");
  ASSERT_GT(expected.size(), 100000u);
  EXPECT_TRUE(sameBytes(mapOf((dir / "scans.simplemap.gz").string(), dir, "gz"), expected));
  EXPECT_TRUE(sameBytes(mapOf((dir / "scans.simplemap").string(), dir, "plain"), expected));
  EXPECT_EQ(jsonNumber(readText(dir / "gz.summary.json"), "scans"), 4);
}

TEST(MapperSimplemap, RangeScanKeyframesGiveThePcdFolderMap) {
  TempDir dir;
  const auto simplemap = lidarSimplemap(Keyframes::RangeScans);
  {
    mrpt::io::CFileOutputStream file((dir / "scans3d.simplemap").string());
    auto archive = mrpt::serialization::archiveFrom(file);
    archive << simplemap;
  }
  EXPECT_TRUE(sameBytes(mapOf((dir / "scans3d.simplemap").string(), dir, "scan3d"),
                        mapOf(kLidar, dir, "pcd")));
}
