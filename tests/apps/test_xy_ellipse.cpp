// The 1-σ ellipse of the xy marginal: against covariances built from known axes and angles.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "ndtom_apps/xy_ellipse.h"

using ndtom::apps::XyEllipse;
using ndtom::apps::xyEllipse;

namespace {

// R diag(a², b², c²) Rᵀ with R a turn of `degrees` about z (counter-clockwise seen from above).
Eigen::Matrix3d covariance(double a, double b, double degrees, double c = 0.3) {
  const Eigen::Matrix3d r =
      Eigen::AngleAxisd(degrees * M_PI / 180, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  return r * Eigen::Vector3d(a * a, b * b, c * c).asDiagonal() * r.transpose();
}

// Axis directions are defined up to a half turn.
double halfTurnDifference(double a, double b) {
  const double d = std::fmod(std::abs(a - b), 180.0);
  return std::min(d, 180.0 - d);
}

}  // namespace

TEST(XyEllipse, AxesAndImageAngleOfARotatedGaussian) {
  for (const double degrees : {0.0, 30.0, 90.0, -60.0, 135.0}) {
    const XyEllipse e = xyEllipse(covariance(2.0, 0.5, degrees));
    EXPECT_NEAR(e.sigma_major, 2.0, 1e-12) << degrees;
    EXPECT_NEAR(e.sigma_minor, 0.5, 1e-12) << degrees;
    // A counter-clockwise turn in the map is a clockwise one in an image whose y points down.
    EXPECT_NEAR(halfTurnDifference(e.image_angle, -degrees), 0.0, 1e-9) << degrees;
  }
}

TEST(XyEllipse, IgnoresTheVerticalAndRoundingBelowZero) {
  Eigen::Matrix3d c = covariance(1.0, 1.0, 0.0, 5.0);
  c(0, 2) = c(2, 0) = 0.4;  // correlation with z does not change the xy marginal
  EXPECT_NEAR(xyEllipse(c).sigma_major, 1.0, 1e-12);
  EXPECT_NEAR(xyEllipse(c).sigma_minor, 1.0, 1e-12);

  Eigen::Matrix3d flat = Eigen::Matrix3d::Zero();
  flat(0, 0) = 4.0;
  flat(1, 1) = -1e-18;  // a flat cell after rounding
  const XyEllipse e = xyEllipse(flat);
  EXPECT_EQ(e.sigma_minor, 0.0);
  EXPECT_NEAR(e.sigma_major, 2.0, 1e-12);
  EXPECT_NEAR(halfTurnDifference(e.image_angle, 0.0), 0.0, 1e-9);
}
