// ndtom-map end to end on the data that ships with the project: the 10 TUM RGB-D frames and
// the 10 lidar scans. Every output must exist and load, and the map must equal the one the
// core builds from the same inputs read with ndtom_io and inserted with NdtMap directly.
// The tolerance is zero (identical bytes): same points, same order, same options; only a
// change in how the program reads or orders the data could make them differ.
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/opengl/COpenGLScene.h>
#include <mrpt/opengl/CSetOfObjects.h>
#include <mrpt/serialization/CArchive.h>

#include <algorithm>
#include <map>
#include <opencv2/imgcodecs.hpp>
#include <thread>

#include "mapper_run.h"
#include "mrpt_ndtom/CNDTOccupancyMap.h"
#include "ndtom/files/map_io.h"
#include "ndtom_io/pcd_reader.h"
#include "ndtom_io/pose_file.h"
#include "ndtom_io/tum_rgbd.h"

using namespace mapper_test;

namespace {

constexpr int kTumDecimation = 4;  // every 4th pixel row and column: fast, still ~40k points

ndtom::NdtMap coreTumMap() {
  ndtom::NdtMap map;
  for (const auto& frame : ndtom::io::readTumSequence(kTum).frames) {
    std::vector<Eigen::Vector3d> points =
        ndtom::io::readDepthImagePoints(frame.depth_path, {}, kTumDecimation);
    for (auto& p : points) p = frame.camera_to_world * p;
    map.insertScan(points, frame.camera_to_world.translation());
  }
  return map;
}

// The first `scans` lidar scans, `passes` times over, as ndtom-map --passes does.
ndtom::NdtMap coreLidarMap(int passes = 1, size_t scans = 10, double resolution = 0.2) {
  const auto poses = ndtom::io::readPoseFile(kLidar + "/poses.txt");
  ndtom::MapOptions options;
  options.resolution = resolution;
  ndtom::NdtMap map(options);
  for (int pass = 0; pass < passes; ++pass)
    for (size_t i = 0; i < std::min(scans, poses.size()); ++i) {
      auto cloud = ndtom::io::readPcd(kLidar + "/full" + std::to_string(i) + ".pcd");
      for (auto& p : cloud.points) p = poses[i].pose * p;
      map.insertScan(cloud.points, poses[i].pose.translation());
    }
  return map;
}

std::string bytesOf(const ndtom::NdtMap& map) {
  const auto bytes = ndtom::encodeMap(map);
  return std::string(bytes.begin(), bytes.end());
}

// A real picture: the right size, many colours, mostly not background, and the height
// colours (saturated pixels) present.
void expectRealPicture(const fs::path& path, int max_width) {
  const cv::Mat image = cv::imread(path.string(), cv::IMREAD_COLOR);
  ASSERT_FALSE(image.empty()) << path;
  EXPECT_GE(image.cols, 480) << path;
  EXPECT_LE(image.cols, max_width) << path;
  EXPECT_GE(image.rows, 300) << path;
  EXPECT_LE(image.rows, 2 * max_width) << path;
  std::map<uint32_t, size_t> histogram;
  size_t saturated = 0;
  for (int r = 0; r < image.rows; ++r)
    for (int c = 0; c < image.cols; ++c) {
      const cv::Vec3b p = image.at<cv::Vec3b>(r, c);
      ++histogram[uint32_t(p[0]) << 16 | uint32_t(p[1]) << 8 | p[2]];
      if (std::max({p[0], p[1], p[2]}) - std::min({p[0], p[1], p[2]}) > 120) ++saturated;
    }
  size_t most_common = 0;
  for (const auto& [color, count] : histogram) most_common = std::max(most_common, count);
  const double pixels = double(image.total());
  EXPECT_GE(histogram.size(), 200u) << path << ": too few colours";
  // Sparse lidar maps leave much background: at least 3% of the picture must be drawn.
  EXPECT_LT(double(most_common) / pixels, 0.97) << path << ": mostly one colour";
  EXPECT_GT(double(saturated) / pixels, 0.01) << path << ": no height colours";
}

const std::vector<std::string> kSuffixes = {".ndtom",   ".ndtommap", ".3Dscene",
                                            ".top.png", ".3d.png",   ".summary.json"};

void expectAllOutputs(const TempDir& dir, const std::string& stem) {
  for (const auto& suffix : kSuffixes)
    EXPECT_TRUE(fs::is_regular_file(dir / (stem + suffix))) << stem + suffix;
  // Nothing left under a temporary name.
  EXPECT_EQ(outputsOf(dir, stem).size(), kSuffixes.size());
}

mrpt_ndtom::CNDTOccupancyMap::Ptr loadMrptMap(const fs::path& path) {
  mrpt::io::CFileGZInputStream file(path.string());
  auto archive = mrpt::serialization::archiveFrom(file);
  return std::dynamic_pointer_cast<mrpt_ndtom::CNDTOccupancyMap>(archive.ReadObject());
}

}  // namespace

TEST(MapperEndToEnd, TumFramesGiveTheCoreMapAndEveryOutput) {
  TempDir dir;
  const ProgramRun run = runMapper(quoted(kTum) + " -o " + quoted((dir / "tum").string()) +
                                       " --decimation-3d-range 4 --image-width 900",
                                   dir);
  ASSERT_EQ(run.exit_code, 0) << run.err;
  expectAllOutputs(dir, "tum");

  const ndtom::NdtMap expected = coreTumMap();
  ASSERT_GT(expected.numGaussians(), 1000u);
  const ndtom::NdtMap loaded = ndtom::loadMap((dir / "tum.ndtom").string());
  EXPECT_EQ(loaded.numGaussians(), expected.numGaussians());
  EXPECT_EQ(loaded.numCells(), expected.numCells());
  EXPECT_TRUE(sameBytes(readText(dir / "tum.ndtom"), bytesOf(expected)));

  // The MRPT object holds the same map; the scene holds the ellipsoids.
  const auto mrpt_map = loadMrptMap(dir / "tum.ndtommap");
  ASSERT_TRUE(mrpt_map);
  EXPECT_TRUE(sameBytes(bytesOf(mrpt_map->ndtMap()), bytesOf(expected)));
  mrpt::opengl::COpenGLScene scene;
  ASSERT_TRUE(scene.loadFromFile((dir / "tum.3Dscene").string()));
  EXPECT_TRUE(scene.getByName("ndtom_gaussians"));

  const std::string summary = readText(dir / "tum.summary.json");
  EXPECT_EQ(jsonNumber(summary, "scans"), 10);
  EXPECT_EQ(jsonNumber(summary, "gaussians", "map"), double(expected.numGaussians()));
  EXPECT_EQ(jsonNumber(summary, "cells", "map"), double(expected.numCells()));
  EXPECT_GT(jsonNumber(summary, "insert_ms_median"), 0);
  EXPECT_GT(jsonNumber(summary, "peak_rss_bytes"), 0);
  // Every stage timed and ended within the run; the peak memory never decreases from one
  // stage's end to the next and ends at the run's peak. The Gaussians are selected, then the
  // scene written, beside the other outputs, which run one by one.
  const double total = jsonNumber(summary, "total_s");
  std::vector<std::pair<double, double>> ends_and_peaks;
  double in_sequence = 0;
  for (const char* stage :
       {"read", "insert", "map", "mrpt_map", "ellipsoids", "scene", "top_view", "view_3d"}) {
    const double seconds = jsonNumber(summary, stage, "stages_s");
    const double end = jsonNumber(summary, stage, "stage_end_s");
    EXPECT_GE(seconds, 0) << stage;
    EXPECT_LE(seconds, end + 1e-6) << stage;
    EXPECT_LE(end, total) << stage;
    if (std::string(stage) != "scene" && std::string(stage) != "ellipsoids") in_sequence += seconds;
    ends_and_peaks.emplace_back(end, jsonNumber(summary, stage, "peak_rss_after_stage_bytes"));
  }
  EXPECT_GE(jsonNumber(summary, "scene", "stage_end_s") - jsonNumber(summary, "scene", "stages_s"),
            jsonNumber(summary, "ellipsoids", "stage_end_s") - 1e-6);
  std::sort(ends_and_peaks.begin(), ends_and_peaks.end());
  double last_peak = 0;
  for (const auto& [end, peak] : ends_and_peaks) {
    // Within 1 MB: the kernel syncs each thread's RSS counts in batches, so /proc's VmHWM
    // can read a few pages lower a moment later (seen: 20 kB).
    EXPECT_GE(peak, last_peak - 1e6) << "stage ending at " << end << " s";
    last_peak = std::max(last_peak, peak);
  }
  EXPECT_GT(jsonNumber(summary, "insert", "stages_s"), 0);
  EXPECT_LE(in_sequence, total);
  EXPECT_GT(ends_and_peaks.back().first, 0.5 * total);  // the stages span most of the run
  EXPECT_LE(last_peak, jsonNumber(summary, "peak_rss_bytes") + 1e6);
  // No --threads: as many as the machine has cores.
  EXPECT_EQ(jsonNumber(summary, "threads"),
            std::clamp(double(std::thread::hardware_concurrency()), 1.0, 256.0));

  expectRealPicture(dir / "tum.top.png", 900);
  expectRealPicture(dir / "tum.3d.png", 900);
  // The terminal summary names the pictures.
  EXPECT_NE(run.out.find((dir / "tum.top.png").string()), std::string::npos) << run.out;
  EXPECT_NE(run.out.find((dir / "tum.3d.png").string()), std::string::npos) << run.out;
}

TEST(MapperEndToEnd, LidarScansGiveTheCoreMapAndEveryOutput) {
  TempDir dir;
  const ProgramRun run = runMapper(
      quoted(kLidar) + " -o " + quoted((dir / "lidar").string()) + " --image-width 800", dir);
  ASSERT_EQ(run.exit_code, 0) << run.err;
  expectAllOutputs(dir, "lidar");
  const ndtom::NdtMap expected = coreLidarMap();
  ASSERT_GT(expected.numGaussians(), 5000u);
  EXPECT_EQ(ndtom::loadMap((dir / "lidar.ndtom").string()).numGaussians(), expected.numGaussians());
  EXPECT_TRUE(sameBytes(readText(dir / "lidar.ndtom"), bytesOf(expected)));
  expectRealPicture(dir / "lidar.top.png", 800);
  expectRealPicture(dir / "lidar.3d.png", 800);
}

TEST(MapperEndToEnd, ThreadsPassesAndCoarseMap) {
  TempDir dir;
  const ProgramRun run =
      runMapper(quoted(kLidar) + " -o " + quoted((dir / "lidar").string()) +
                    " --threads 2 --passes 3 --coarse 3 --no-pictures --max-scans 4 "
                    "--resolution 0.4",
                dir);
  ASSERT_EQ(run.exit_code, 0) << run.err;
  // Threads do not change the map; three passes are the scans inserted three times.
  const ndtom::NdtMap expected = coreLidarMap(3, 4, 0.4);
  EXPECT_TRUE(sameBytes(readText(dir / "lidar.ndtom"), bytesOf(expected)));
  EXPECT_TRUE(sameBytes(readText(dir / "lidar.coarse3.ndtom"), bytesOf(expected.coarsened(3))));
  EXPECT_FALSE(fs::exists(dir / "lidar.top.png"));

  const std::string summary = readText(dir / "lidar.summary.json");
  EXPECT_EQ(jsonNumber(summary, "threads"), 2);
  EXPECT_EQ(jsonNumber(summary, "pass", "passes"), 1);
  EXPECT_EQ(jsonNumber(summary, "cells_drift_percent"), 0);  // same scans, same cells
  EXPECT_LT(jsonNumber(summary, "map_bytes_drift_percent"), 1.0);
  EXPECT_EQ(jsonNumber(summary, "gaussians", "coarse_map"),
            double(expected.coarsened(3).numGaussians()));
  size_t passes = 0;
  for (size_t at = 0; (at = summary.find("\"pass\":", at)) != std::string::npos; ++at) ++passes;
  EXPECT_EQ(passes, 3u);
  EXPECT_NE(run.out.find("pass 3"), std::string::npos) << run.out;
}
