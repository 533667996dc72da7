// The 3D picture's ray caster against brute force: which pixels an ellipsoid covers and at
// what depth, found by marching along each pixel's ray; occlusion whatever the drawing order;
// the path hidden behind surfaces.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <random>

#include "ndtom_apps/depth_canvas.h"

namespace ndtom::apps {
namespace {

const cv::Vec3b kWhite(255, 255, 255), kRed(0, 0, 200), kBlue(200, 0, 0);

ViewCamera smallCamera() {
  return ViewCamera::orbiting(Eigen::Vector3d(1, 2, 0.5), 6.0, -60, 35, 40, cv::Size(120, 90));
}

// The first depth along the pixel's ray inside the ellipsoid (no farther than `reach` from
// its centre), by steps of `step`, or +inf.
double marchedDepth(const ViewCamera& camera, int x, int y, const Eigen::Vector3d& centre,
                    const Eigen::Matrix3d& shape_inverse, double reach, double step) {
  const Eigen::Vector3d d = camera.rayThrough(x + 0.5, y + 0.5);
  const double centre_depth = (centre - camera.eye).dot(camera.forward);
  // Depth is the ray's parameter; every point of the ellipsoid lies within `reach` in depth.
  for (double t = centre_depth - reach; t < centre_depth + reach; t += step) {
    const Eigen::Vector3d q = camera.eye + t * d - centre;
    if (q.dot(shape_inverse * q) <= 1) return t;
  }
  return std::numeric_limits<double>::infinity();
}

TEST(DepthCanvas, EllipsoidCoversThePixelsWhoseRaysEnterIt) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> axis(0.2, 1.2), angle(-M_PI, M_PI);
  const ViewCamera camera = smallCamera();
  for (int trial = 0; trial < 4; ++trial) {
    const Eigen::Matrix3d rotation =
        (Eigen::AngleAxisd(angle(rng), Eigen::Vector3d::UnitZ()) *
         Eigen::AngleAxisd(angle(rng), Eigen::Vector3d::UnitX()))
            .toRotationMatrix();
    const Eigen::Vector3d radii(axis(rng), axis(rng), 0.3 * axis(rng));
    const Eigen::Matrix3d shape =
        rotation * radii.cwiseAbs2().asDiagonal() * rotation.transpose();
    const Eigen::Vector3d centre(1 + 0.3 * trial, 2, 0.5);
    DepthCanvas canvas(camera, kWhite);
    canvas.drawEllipsoid(centre, shape, kRed);
    const Eigen::Matrix3d inverse = shape.inverse();
    size_t covered = 0, disagree = 0;
    for (int y = 0; y < camera.size.height; ++y)
      for (int x = 0; x < camera.size.width; ++x) {
        const double marched = marchedDepth(camera, x, y, centre, inverse, radii.maxCoeff(), 0.002);
        const double drawn = canvas.depth()(y, x);
        const bool hit = std::isfinite(marched);
        covered += hit;
        if (hit != std::isfinite(drawn)) {
          ++disagree;  // only a ray grazing the surface may be missed by the steps
          continue;
        }
        if (hit) {
          EXPECT_NEAR(drawn, marched, 0.0025) << trial << " at " << x << "," << y;
          EXPECT_NE(canvas.image()(y, x), kWhite);
        } else {
          EXPECT_EQ(canvas.image()(y, x), kWhite);
        }
      }
    EXPECT_GT(covered, 100u) << trial;
    EXPECT_LE(disagree, covered / 50) << trial << ": " << disagree << " of " << covered;
  }
}

TEST(DepthCanvas, NearerSurfaceWinsWhateverTheOrder) {
  const ViewCamera camera = smallCamera();
  const Eigen::Vector3d target(1, 2, 0.5);
  const Eigen::Vector3d near = target - 1.5 * camera.forward, far = target + 1.5 * camera.forward;
  const Eigen::Matrix3d ball = 0.36 * Eigen::Matrix3d::Identity();
  DepthCanvas near_first(camera, kWhite), far_first(camera, kWhite);
  near_first.drawEllipsoid(near, ball, kRed);
  near_first.drawEllipsoid(far, ball, kBlue);
  far_first.drawEllipsoid(far, ball, kBlue);
  far_first.drawEllipsoid(near, ball, kRed);
  EXPECT_EQ(cv::norm(near_first.image(), far_first.image(), cv::NORM_INF), 0);
  // The centre pixel shows the near ball, lit: red only.
  const cv::Vec3b centre = near_first.image()(camera.size.height / 2, camera.size.width / 2);
  EXPECT_GT(centre[2], 0);
  EXPECT_EQ(centre[0], 0);
  EXPECT_NEAR(near_first.depth()(camera.size.height / 2, camera.size.width / 2),
              (near - camera.eye).dot(camera.forward) - 0.6, 0.02);
}

TEST(DepthCanvas, LitSideIsBrighterThanTheShadedSide) {
  const ViewCamera camera = smallCamera();
  DepthCanvas canvas(camera, kWhite);
  canvas.drawEllipsoid(Eigen::Vector3d(1, 2, 0.5), 0.8 * Eigen::Matrix3d::Identity(), kRed);
  // The light is above the camera: the top of the ball is brighter than its bottom.
  int top = -1, bottom = -1;
  const int x = camera.size.width / 2;
  for (int y = 0; y < camera.size.height; ++y)
    if (std::isfinite(canvas.depth()(y, x))) {
      if (top < 0) top = y;
      bottom = y;
    }
  ASSERT_GE(top, 0);
  EXPECT_GT(canvas.image()(top + 2, x)[2], canvas.image()(bottom - 2, x)[2]);
}

TEST(DepthCanvas, PathIsHiddenBehindSurfaces) {
  const ViewCamera camera = smallCamera();
  const Eigen::Vector3d target(1, 2, 0.5);
  DepthCanvas canvas(camera, kWhite);
  canvas.drawEllipsoid(target - camera.forward, 0.25 * Eigen::Matrix3d::Identity(), kRed);
  // A horizontal line across the picture behind the ball.
  const Eigen::Vector3d behind = target + 2 * camera.forward;
  canvas.drawPolyline({behind - 4 * camera.right, behind + 4 * camera.right}, cv::Vec3b(0, 0, 0),
                      1);
  const Eigen::Vector3d mid = camera.project(behind);
  const int y = int(std::floor(mid.y()));
  size_t black = 0, red = 0;
  for (int x = 0; x < camera.size.width; ++x) {
    const cv::Vec3b p = canvas.image()(y, x);
    black += p == cv::Vec3b(0, 0, 0);
    red += p[2] > 0 && p[0] == 0 && p != kWhite;
  }
  EXPECT_GT(red, 5u);    // the ball covers the middle of the line
  EXPECT_GT(black, 60u);  // the rest of the line shows
  EXPECT_NE(canvas.image()(y, int(mid.x())), cv::Vec3b(0, 0, 0));
}

TEST(DepthCanvas, SkipsEllipsoidsAroundOrBehindTheEye) {
  const ViewCamera camera = smallCamera();
  DepthCanvas canvas(camera, kWhite);
  canvas.drawEllipsoid(camera.eye, Eigen::Matrix3d::Identity(), kRed);
  canvas.drawEllipsoid(camera.eye - 3 * camera.forward, Eigen::Matrix3d::Identity(), kRed);
  canvas.drawEllipsoid(Eigen::Vector3d(1, 2, 0.5), Eigen::Matrix3d::Zero(), kRed);  // singular
  EXPECT_EQ(cv::countNonZero(canvas.depth() < std::numeric_limits<float>::infinity()), 0);
}

}  // namespace
}  // namespace ndtom::apps
