// Real data: 10 TUM RGB-D frames (fr2/pioneer_slam2) with motion-capture poses. The hall's
// floor lies at world z ≈ 0, so after mapping at 0.1 m it must come out as flat, horizontal
// Gaussians at z ≈ 0. The same check run with a transposed rotation, wrong intrinsics or a
// wrong depth scale must fail: that is what makes it a test of the geometry.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <algorithm>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <sstream>

#include "ndtom/map/ndt_map.h"

using Eigen::Vector3d;

namespace {

const std::string kTumDir = std::string(NDTOM_SOURCE_DIR) + "/share/data/tum-fr2-pioneer-slam2";

struct Frame {
  std::string depth_file;
  Eigen::Isometry3d camera_to_world;
};

std::vector<Frame> readAssociations() {
  std::ifstream in(kTumDir + "/associations.txt");
  EXPECT_TRUE(in.good()) << "missing " << kTumDir;
  std::vector<Frame> frames;
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream s(line);
    std::string rgb, depth;
    double tx, ty, tz, qx, qy, qz, qw;
    s >> rgb >> depth >> tx >> ty >> tz >> qx >> qy >> qz >> qw;
    Frame f;
    f.depth_file = kTumDir + "/" + depth;
    f.camera_to_world.setIdentity();
    f.camera_to_world.linear() = Eigen::Quaterniond(qw, qx, qy, qz).normalized().toRotationMatrix();
    f.camera_to_world.translation() = Vector3d(tx, ty, tz);
    frames.push_back(f);
  }
  return frames;
}

struct Geometry {
  // TUM's default for registered depth. (The published fr2 calibration, 520.9/521.0/325.1/
  // 249.7, belongs to the unregistered depth image: with it the floor sits 4 cm higher.)
  double fx = 525.0, fy = 525.0, cx = 319.5, cy = 239.5;
  double depth_scale = 5000.0;  // raw units per metre
  bool transpose_rotation = false;
};

// Back-projects every second pixel of every frame and maps the scans at 0.1 m.
ndtom::NdtMap mapFrames(const std::vector<Frame>& frames, const Geometry& g) {
  ndtom::MapOptions options;
  options.resolution = 0.1;
  ndtom::NdtMap map(options);
  for (const Frame& f : frames) {
    const cv::Mat depth = cv::imread(f.depth_file, cv::IMREAD_UNCHANGED);
    EXPECT_EQ(depth.type(), CV_16UC1) << f.depth_file;
    if (depth.type() != CV_16UC1) continue;
    Eigen::Isometry3d pose = f.camera_to_world;
    if (g.transpose_rotation) pose.linear().transposeInPlace();
    std::vector<Vector3d> points;
    for (int v = 0; v < depth.rows; v += 2)
      for (int u = 0; u < depth.cols; u += 2) {
        const uint16_t raw = depth.at<uint16_t>(v, u);
        if (raw == 0) continue;
        const double z = raw / g.depth_scale;
        points.push_back(pose * Vector3d((u - g.cx) * z / g.fx, (v - g.cy) * z / g.fy, z));
      }
    map.insertScan(points, pose.translation());
  }
  return map;
}

struct FloorCheck {
  int candidates = 0;         // Gaussians with N >= 10 whose mean is within 0.1 m of z = 0
  int horizontal = 0;         // of those: normal (smallest eigenvector) within 10° of vertical
  double median_z = NAN;      // median height of the horizontal ones (m)
  double median_sigma = NAN;  // their median thickness sqrt(λ_min) (m)
};

double median(std::vector<double> v) {
  if (v.empty()) return NAN;
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

FloorCheck checkFloor(const ndtom::NdtMap& map) {
  FloorCheck c;
  std::vector<double> heights, sigmas;
  map.forEachGaussian(
      [&](const ndtom::Gaussian& g) {
        if (g.n < 10 || std::abs(g.mean.z()) > 0.1) return;
        ++c.candidates;
        Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(g.covariance);
        if (std::abs(eig.eigenvectors().col(0).z()) < std::cos(10.0 * M_PI / 180.0)) return;
        ++c.horizontal;
        heights.push_back(g.mean.z());
        sigmas.push_back(std::sqrt(std::max(0.0, eig.eigenvalues()[0])));
      },
      ndtom::Covariance::Exact);
  c.median_z = median(heights);
  c.median_sigma = median(sigmas);
  return c;
}

std::ostream& operator<<(std::ostream& os, const FloorCheck& c) {
  return os << c.horizontal << " horizontal of " << c.candidates << " candidates, median z "
            << c.median_z << " m, median thickness " << c.median_sigma << " m";
}

// The criterion: at least 1000 horizontal Gaussians near z = 0, making up at least 70 % of
// the candidates there, with median height within 2 cm of 0 and median thickness < 1 cm.
bool floorIsFlatAtZero(const FloorCheck& c) {
  return c.horizontal >= 1000 && c.horizontal >= 0.7 * c.candidates &&
         std::abs(c.median_z) < 0.02 && c.median_sigma < 0.01;
}

}  // namespace

TEST(TumFloor, FloorIsFlatHorizontalGaussiansAtZero) {
  const auto frames = readAssociations();
  ASSERT_EQ(frames.size(), 10u);
  const FloorCheck c = checkFloor(mapFrames(frames, Geometry{}));
  std::cout << "floor: " << c << "\n";
  EXPECT_TRUE(floorIsFlatAtZero(c)) << c;
}

TEST(TumFloor, WrongGeometryBreaksTheFloor) {
  const auto frames = readAssociations();
  ASSERT_EQ(frames.size(), 10u);
  Geometry transposed;
  transposed.transpose_rotation = true;
  Geometry wrong_intrinsics;  // the fr1 calibration's focal length scaled by 1.2
  wrong_intrinsics.fx = wrong_intrinsics.fy = 630.0;
  Geometry wrong_centre;
  wrong_centre.cy = 300.0;
  Geometry wrong_scale;
  wrong_scale.depth_scale = 5000.0 * 1.1;
  for (const auto& [name, g] : {std::pair{"transposed rotation", transposed},
                                {"focal length 630", wrong_intrinsics},
                                {"principal point cy 300", wrong_centre},
                                {"depth scale 5500", wrong_scale}}) {
    const FloorCheck c = checkFloor(mapFrames(frames, g));
    std::cout << name << ": " << c << "\n";
    EXPECT_FALSE(floorIsFlatAtZero(c)) << name << ": " << c;
  }
}
