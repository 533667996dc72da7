// KITTI and TUM trajectory files.
#include <gtest/gtest.h>

#include <fstream>

#include "ndtom_io/pose_file.h"
#include "support/special_files.h"

using ndtom::io::PoseFileError;
using ndtom::io::readPoseFile;

namespace {

std::string writeTemp(const std::string& name, const std::string& text) {
  const std::string path = ::testing::TempDir() + "/" + name;
  std::ofstream(path) << text;
  return path;
}

}  // namespace

TEST(PoseFile, KittiRowMajor) {
  // 90° about z, then translation (1, 2, 3).
  const auto poses = readPoseFile(writeTemp("k.txt", "0 -1 0 1 1 0 0 2 0 0 1 3\n"));
  ASSERT_EQ(poses.size(), 1u);
  EXPECT_TRUE((poses[0].pose * Eigen::Vector3d(1, 0, 0)).isApprox(Eigen::Vector3d(1, 3, 3)));
}

TEST(PoseFile, TumQuaternionIsXyzw) {
  const double s = std::sqrt(0.5);
  const auto poses =
      readPoseFile(writeTemp("t.txt", "# t tx ty tz qx qy qz qw\n12.5 1 2 3 0 0 " +
                                          std::to_string(s) + " " + std::to_string(s) + "\n"));
  ASSERT_EQ(poses.size(), 1u);
  EXPECT_EQ(poses[0].time, 12.5);
  EXPECT_TRUE((poses[0].pose * Eigen::Vector3d(1, 0, 0)).isApprox(Eigen::Vector3d(1, 3, 3), 1e-6));
}

TEST(PoseFile, RealKittiFileHasOnePosePerScan) {
  const auto poses = readPoseFile(std::string(NDTOM_TEST_DATA_DIR) + "/balm-realworld/poses.txt");
  EXPECT_EQ(poses.size(), 10u);
  for (const auto& p : poses) EXPECT_NEAR(p.pose.linear().determinant(), 1.0, 1e-12);
}

TEST(PoseFile, ErrorsNameFileAndLine) {
  const std::string bad = writeTemp("bad.txt", "1 2 3 4 5 6 7 8\n1 2 3\n");
  try {
    readPoseFile(bad);
    FAIL();
  } catch (const PoseFileError& e) {
    EXPECT_NE(std::string(e.what()).find("line 2"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(bad), std::string::npos) << e.what();
  }
  EXPECT_THROW(readPoseFile(writeTemp("nan.txt", "1 nan 0 0 0 0 0 1\n")), PoseFileError);
  EXPECT_THROW(readPoseFile(writeTemp("zeroq.txt", "1 0 0 0 0 0 0 0\n")), PoseFileError);
  EXPECT_THROW(readPoseFile(writeTemp("notrot.txt", "2 0 0 0 0 1 0 0 0 0 1 0\n")), PoseFileError);
  EXPECT_THROW(readPoseFile(writeTemp("empty.txt", "# nothing\n")), PoseFileError);
  EXPECT_THROW(readPoseFile("/nonexistent/poses.txt"), PoseFileError);
}

// A pose with determinant -1 is a mirror, not a rotation: it was accepted and turned the
// scans inside out. A file mixing KITTI and TUM lines was accepted as one trajectory.
TEST(PoseFile, MirrorsAndMixedFormatsAreRejected) {
  const std::string mirror = writeTemp("mirror.txt", "-1 0 0 0 0 1 0 0 0 0 1 0\n");
  try {
    readPoseFile(mirror);
    FAIL() << "a mirror was accepted";
  } catch (const PoseFileError& e) {
    EXPECT_NE(std::string(e.what()).find("line 1: the 3x3 block is not a rotation"),
              std::string::npos)
        << e.what();
  }
  const std::string mixed = writeTemp("mixed.txt", "1 0 0 0 0 1 0 0 0 0 1 0\n5.0 1 2 3 0 0 0 1\n");
  try {
    readPoseFile(mixed);
    FAIL() << "a file mixing KITTI and TUM lines was accepted";
  } catch (const PoseFileError& e) {
    EXPECT_NE(std::string(e.what()).find("line 2: expected KITTI"), std::string::npos) << e.what();
  }
  ndtom::io::PoseFormat used = ndtom::io::PoseFormat::Auto;
  readPoseFile(writeTemp("tum2.txt", "# t x y z qx qy qz qw\n5.0 1 2 3 0 0 0 1\n"),
               ndtom::io::PoseFormat::Auto, &used);
  EXPECT_EQ(used, ndtom::io::PoseFormat::Tum);
}

TEST(PoseFile, RefusesFilesThatAreNotRegularFiles) {
  const ndtom::testing::Fifo fifo(::testing::TempDir() + "/poses-fifo.txt");
  for (const std::string& path : {fifo.path(), ndtom::testing::kEndlessFile}) {
    try {
      readPoseFile(path);
      FAIL() << path << " accepted";
    } catch (const PoseFileError& e) {
      EXPECT_NE(std::string(e.what()).find("not a regular file"), std::string::npos) << e.what();
    }
  }
}
