// TUM RGB-D sequences: the layouts TUM publishes, and back-projection of depth images.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>

#include "ndtom_io/tum_rgbd.h"
#include "support/special_files.h"

namespace fs = std::filesystem;
using ndtom::io::readTumSequence;

namespace {

const std::string kTum = std::string(NDTOM_SOURCE_DIR) + "/share/data/tum-fr2-pioneer-slam2";

fs::path freshDir(const std::string& name) {
  const fs::path dir = fs::path(::testing::TempDir()) / name;
  fs::remove_all(dir);
  fs::create_directories(dir / "depth");
  return dir;
}

}  // namespace

TEST(TumRgbd, ShippedSequenceWithPosesInAssociations) {
  const auto seq = readTumSequence(kTum);
  ASSERT_EQ(seq.frames.size(), 10u);
  EXPECT_NEAR(seq.frames[0].camera_to_world.translation().x(), -2.2591, 1e-12);
  EXPECT_NEAR(seq.frames[0].time, 1311877813.991479, 1e-6);
  EXPECT_TRUE(fs::exists(seq.frames[9].depth_path));
}

TEST(TumRgbd, DepthListWithGroundTruthMatchedByTime) {
  const fs::path dir = freshDir("tum_depth_txt");
  std::ofstream(dir / "depth.txt")
      << "# depth\n10.000 depth/a.png\n10.500 depth/b.png\n20.0 depth/c.png\n";
  std::ofstream(dir / "groundtruth.txt") << "# gt\n9.995 1 0 0 0 0 0 1\n10.01 2 0 0 0 0 0 1\n"
                                            "10.49 3 0 0 0 0 0 1\n";
  const auto seq = readTumSequence(dir.string());
  ASSERT_EQ(seq.frames.size(), 2u);
  EXPECT_EQ(seq.frames_without_pose, 1u);                           // 20.0 has no pose within 20 ms
  EXPECT_EQ(seq.frames[0].camera_to_world.translation().x(), 1.0);  // 9.995 is nearer than 10.01
  EXPECT_EQ(seq.frames[1].camera_to_world.translation().x(), 3.0);
}

TEST(TumRgbd, AssociatePyOutputWithGroundTruth) {
  const fs::path dir = freshDir("tum_assoc4");
  std::ofstream(dir / "associations.txt") << "5.0 rgb/x.png 5.001 depth/x.png\n";
  std::ofstream(dir / "groundtruth.txt") << "5.0 7 8 9 0 0 0 1\n";
  const auto seq = readTumSequence(dir.string());
  ASSERT_EQ(seq.frames.size(), 1u);
  EXPECT_EQ(seq.frames[0].camera_to_world.translation(), Eigen::Vector3d(7, 8, 9));
}

TEST(TumRgbd, BadSequencesGiveClearErrors) {
  EXPECT_THROW(readTumSequence("/nonexistent"), ndtom::io::TumError);
  const fs::path dir = freshDir("tum_empty");
  EXPECT_THROW(readTumSequence(dir.string()), ndtom::io::TumError);
  std::ofstream(dir / "associations.txt") << "a b c\n";
  EXPECT_THROW(readTumSequence(dir.string()), ndtom::io::TumError);
}

TEST(TumRgbd, BackProjectionInvertsThePinholeModel) {
  cv::Mat depth(4, 6, CV_16UC1, cv::Scalar(0));
  depth.at<uint16_t>(1, 5) = 10000;  // 2 m at pixel (u=5, v=1)
  depth.at<uint16_t>(3, 0) = 2500;   // 0.5 m at (0, 3)
  const std::string png = ::testing::TempDir() + "/depth.png";
  ASSERT_TRUE(cv::imwrite(png, depth));
  ndtom::io::DepthCamera cam;
  cam.fx = 100;
  cam.fy = 200;
  cam.cx = 2;
  cam.cy = 1.5;
  const auto pts = ndtom::io::readDepthImagePoints(png, cam);
  ASSERT_EQ(pts.size(), 2u);
  // Project back: u = fx·x/z + cx, v = fy·y/z + cy.
  EXPECT_NEAR(cam.fx * pts[0].x() / pts[0].z() + cam.cx, 5, 1e-12);
  EXPECT_NEAR(cam.fy * pts[0].y() / pts[0].z() + cam.cy, 1, 1e-12);
  EXPECT_DOUBLE_EQ(pts[0].z(), 2.0);
  EXPECT_DOUBLE_EQ(pts[1].z(), 0.5);
  cam.depth_scale = 0;
  EXPECT_THROW(ndtom::io::readDepthImagePoints(png, cam), std::invalid_argument);
  EXPECT_THROW(ndtom::io::readDepthImagePoints("/nonexistent.png", ndtom::io::DepthCamera{}),
               ndtom::io::TumError);
}

// Image sizes are bounded before decoding: a 5000 x 5000 PNG of zeros (a few kB) was decoded
// (50 MB) and its points reserved (600 MB) before a pixel was read.
TEST(TumRgbd, DepthImageSizeIsBoundedBeforeDecoding) {
  const std::string png = ::testing::TempDir() + "/large-depth.png";
  ASSERT_TRUE(cv::imwrite(png, cv::Mat(5000, 5000, CV_16UC1, cv::Scalar(0))));
  auto message = [&](int decimation, uint64_t max_points) {
    try {
      ndtom::io::readDepthImagePoints(png, ndtom::io::DepthCamera{}, decimation, max_points);
    } catch (const ndtom::io::TumError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_NE(message(1, ndtom::io::kMaxDepthImagePixels).find("5000 x 5000 pixels"),
            std::string::npos);
  cv::imwrite(png, cv::Mat(480, 640, CV_16UC1, cv::Scalar(1000)));
  EXPECT_NE(message(1, 1000).find("up to 307200 points"), std::string::npos) << message(1, 1000);
  EXPECT_EQ(message(32, 1000), "accepted");  // 15 x 20 points
  EXPECT_EQ(ndtom::io::readDepthImagePoints(png, ndtom::io::DepthCamera{}, 32, 1000).size(), 300u);
  std::remove(png.c_str());
}

TEST(TumRgbd, RefusesFilesThatAreNotRegularFiles) {
  const ndtom::testing::Fifo fifo(::testing::TempDir() + "/depth-fifo.png");
  for (const std::string& path : {fifo.path(), ndtom::testing::kEndlessFile}) {
    try {
      ndtom::io::readDepthImagePoints(path, ndtom::io::DepthCamera{});
      FAIL() << path << " accepted";
    } catch (const ndtom::io::TumError& e) {
      EXPECT_NE(std::string(e.what()).find("not a regular file"), std::string::npos) << e.what();
    }
  }
  const fs::path dir = freshDir("tum_fifo_table");
  const ndtom::testing::Fifo table((dir / "associations.txt").string());
  EXPECT_THROW(readTumSequence(dir.string()), ndtom::io::TumError);
}
