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

// The writer against the reader: every translation back bit for bit, every rotation to its
// last bits (the reader re-orthonormalises), and the text holds the exact doubles.
TEST(PoseFile, KittiWriterRoundTripsThroughTheReader) {
  std::vector<Eigen::Isometry3d> written;
  for (int i = 0; i < 50; ++i) {
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    pose.linear() = Eigen::AngleAxisd(0.37 * i - 3, Eigen::Vector3d(1, 0.1 * i, -2).normalized())
                        .toRotationMatrix();
    pose.translation() = Eigen::Vector3d(1e3 / 3 * i, -0.1 - i * M_PI, 1e-7 * i * i);
    written.push_back(pose);
  }
  const std::string path = ::testing::TempDir() + "/written_poses.txt";
  ndtom::io::writeKittiPoseFile(path, written);
  ndtom::io::PoseFormat format = ndtom::io::PoseFormat::Auto;
  const auto read = readPoseFile(path, ndtom::io::PoseFormat::Auto, &format);
  EXPECT_EQ(format, ndtom::io::PoseFormat::Kitti);
  ASSERT_EQ(read.size(), written.size());
  std::ifstream text(path);
  for (size_t i = 0; i < written.size(); ++i) {
    EXPECT_EQ(read[i].time, double(i));
    for (int k = 0; k < 3; ++k) EXPECT_EQ(read[i].pose.translation()[k], written[i].translation()[k]);
    EXPECT_LT((read[i].pose.linear() - written[i].linear()).cwiseAbs().maxCoeff(), 1e-15);
    for (int row = 0; row < 3; ++row)
      for (int col = 0; col < 4; ++col) {
        double x = 0;
        ASSERT_TRUE(text >> x);
        EXPECT_EQ(x, written[i].matrix()(row, col)) << "line " << i + 1;
      }
  }
  EXPECT_EQ(ndtom::io::kittiPoseText({}), "");
  EXPECT_THROW(ndtom::io::writeKittiPoseFile(::testing::TempDir() + "/no/such/folder/p.txt", written),
               PoseFileError);
}
