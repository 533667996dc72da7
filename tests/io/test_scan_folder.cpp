// io::ScanFolder, the reader of a folder of .pcd scans + poses.txt, and io::filterPoints: the
// scans in natural order paired with the pose file's lines, the files' points as readPcd reads
// them, every refusal named, and the filter against a loop over the file's rows.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <random>

#include "ndtom_io/scan_folder.h"
#include "support/thrown_message.h"

namespace fs = std::filesystem;
using namespace ndtom::io;
using ndtom::testing::thrownMessage;

namespace {

class Folder {
 public:
  explicit Folder(const std::string& name) : path_(fs::path(::testing::TempDir()) / name) {
    fs::remove_all(path_);
    fs::create_directories(path_);
  }
  ~Folder() { fs::remove_all(path_); }
  std::string path() const { return path_.string(); }
  std::string operator/(const std::string& name) const { return (path_ / name).string(); }

 private:
  fs::path path_;
};

Eigen::Isometry3d shifted(double x) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation() = Eigen::Vector3d(x, 0, 0);
  return pose;
}

// Scans named so that plain string order would differ: full0, full2, full10, each holding one
// point (i, 0, 0); pose j moves by j metres.
void writeThreeScans(const Folder& folder, bool poses) {
  for (const int i : {10, 0, 2})
    writePcdBinary(folder / ("full" + std::to_string(i) + ".pcd"), {{double(i), 0, 0}});
  if (poses) writeKittiPoseFile(folder / "poses.txt", {shifted(0), shifted(1), shifted(2)});
}

}  // namespace

TEST(ScanFolder, ScansInNaturalOrderWithTheirLines) {
  Folder folder("scan_folder_order");
  writeThreeScans(folder, true);
  const ScanFolder scans(folder.path());
  ASSERT_EQ(scans.size(), 3u);
  EXPECT_EQ(scans.fileName(0), "full0.pcd");
  EXPECT_EQ(scans.fileName(1), "full2.pcd");
  EXPECT_EQ(scans.fileName(2), "full10.pcd");
  ASSERT_TRUE(scans.hasPoses());
  EXPECT_EQ(scans.posesPath(), folder / "poses.txt");
  for (size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(scans.poses()[i].pose.translation().x(), double(i));
    EXPECT_EQ(scans.read(i).points, readPcd(folder / scans.fileName(i)).points);
  }
  EXPECT_THROW(scans.read(3), std::out_of_range);
}

TEST(ScanFolder, TheShippedLidarScans) {
  const std::string dir = std::string(NDTOM_TEST_DATA_DIR) + "/balm-realworld";
  const ScanFolder scans(dir);
  ASSERT_EQ(scans.size(), 10u);
  const std::vector<StampedPose> poses = readPoseFile(dir + "/poses.txt");
  for (size_t i = 0; i < scans.size(); ++i) {
    EXPECT_EQ(scans.fileName(i), "full" + std::to_string(i) + ".pcd");
    EXPECT_TRUE(scans.poses()[i].pose.isApprox(poses[i].pose, 0));
  }
  EXPECT_EQ(scans.read(3).points, readPcd(dir + "/full3.pcd").points);
}

TEST(ScanFolder, WithoutPoses) {
  Folder folder("scan_folder_no_poses");
  writeThreeScans(folder, false);
  EXPECT_EQ(thrownMessage([&] { ScanFolder{folder.path()}; }),
            folder / "poses.txt" + ": no pose file");
  ScanFolderOptions optional;
  optional.poses_required = false;
  const ScanFolder scans(folder.path(), optional);
  EXPECT_EQ(scans.size(), 3u);
  EXPECT_FALSE(scans.hasPoses());
  EXPECT_EQ(scans.posesPath(), folder / "poses.txt");
  // A pose file that was asked for must be there.
  optional.poses_file = folder / "other.txt";
  EXPECT_EQ(thrownMessage([&] { ScanFolder(folder.path(), optional); }),
            folder / "other.txt" + ": no pose file");
}

TEST(ScanFolder, RefusalsNameTheFolderOrFile) {
  Folder folder("scan_folder_errors");
  EXPECT_EQ(thrownMessage([&] { ScanFolder{folder / "missing"}; }),
            folder / "missing" + ": not a folder of .pcd files");
  EXPECT_EQ(thrownMessage([&] { ScanFolder{folder.path()}; }), folder.path() + ": no .pcd files");
  writeThreeScans(folder, false);
  writeKittiPoseFile(folder / "poses.txt", {shifted(0), shifted(1)});
  EXPECT_EQ(thrownMessage([&] { ScanFolder{folder.path()}; }),
            folder / "poses.txt" + ": 2 poses for 3 .pcd files in " + folder.path() +
                " (line i is the pose of the i-th scan)");
}

TEST(FilterPoints, KeepsAllByDefault) {
  std::vector<Eigen::Vector3d> points = {{NAN, 0, 0}, {0, 0, 0}, {1, 2, 3}};
  const std::vector<Eigen::Vector3d> before = points;
  const DroppedPoints dropped = filterPoints(points, {});
  EXPECT_EQ(points.size(), 3u);
  EXPECT_TRUE(points[2] == before[2] && points[1] == before[1] && std::isnan(points[0].x()));
  EXPECT_EQ(dropped.decimated + dropped.invalid, 0u);
}

TEST(FilterPoints, EmptyInput) {
  std::vector<Eigen::Vector3d> points;
  const DroppedPoints dropped = filterPoints(points, {3, true, true});
  EXPECT_TRUE(points.empty());
  EXPECT_EQ(dropped.decimated + dropped.invalid, 0u);
}

// Oracle: row i is kept if i is a multiple of N and the point is valid, by the definition.
TEST(FilterPoints, MatchesARowByRowLoop) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> coordinate(-5, 5);
  std::vector<Eigen::Vector3d> rows;
  for (int i = 0; i < 500; ++i) {
    const int kind = int(rng() % 6);
    if (kind == 0)
      rows.emplace_back(NAN, 1, 1);
    else if (kind == 1)
      rows.emplace_back(0, 0, 0);
    else if (kind == 2)
      rows.emplace_back(1, INFINITY, 0);
    else
      rows.emplace_back(coordinate(rng), coordinate(rng), coordinate(rng));
  }
  for (const uint32_t n : {0u, 1u, 2u, 3u, 7u})
    for (const bool non_finite : {false, true})
      for (const bool origin : {false, true}) {
        std::vector<Eigen::Vector3d> expected;
        size_t invalid = 0;
        for (size_t i = 0; i < rows.size(); ++i) {
          if (n > 1 && i % n != 0) continue;
          const Eigen::Vector3d& p = rows[i];
          const bool finite = std::isfinite(p.x()) && std::isfinite(p.y()) && std::isfinite(p.z());
          const bool zero = p.x() == 0 && p.y() == 0 && p.z() == 0;
          if ((non_finite && !finite) || (origin && zero)) {
            ++invalid;
            continue;
          }
          expected.push_back(p);
        }
        std::vector<Eigen::Vector3d> points = rows;
        const DroppedPoints dropped = filterPoints(points, {n, non_finite, origin});
        ASSERT_EQ(points.size(), expected.size()) << n << non_finite << origin;
        for (size_t i = 0; i < points.size(); ++i)  // bit for bit, NaN included
          EXPECT_EQ(std::memcmp(points[i].data(), expected[i].data(), sizeof(double) * 3), 0);
        EXPECT_EQ(dropped.invalid, invalid);
        EXPECT_EQ(dropped.decimated, rows.size() - expected.size() - invalid);
      }
}
