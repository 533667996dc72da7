#include <Eigen/Eigenvalues>
#include <cmath>
#include <random>

#include "ndtom/localization/global_localization.h"

namespace ndtom {
namespace {

constexpr double kInlierDistance = 0.05;  // m
constexpr int kTrials = 300;
constexpr size_t kMaxSample = 20000;  // points the inliers are counted on
constexpr double kMinHeight = 0.1;    // m: a plane through the sensor is no ground

}  // namespace

GravityGuess findGround(const std::vector<Eigen::Vector3d>& scan, double max_tilt_deg) {
  std::vector<Eigen::Vector3d> points;
  const size_t stride = scan.size() / kMaxSample + 1;
  for (size_t i = 0; i < scan.size(); i += stride)
    if (scan[i].allFinite()) points.push_back(scan[i]);
  GravityGuess best;
  if (points.size() < 3) return best;
  const double min_up_z = std::cos(max_tilt_deg * M_PI / 180);
  std::mt19937 rng(7);
  std::uniform_int_distribution<size_t> pick(0, points.size() - 1);
  for (int trial = 0; trial < kTrials; ++trial) {
    const Eigen::Vector3d& a = points[pick(rng)];
    const Eigen::Vector3d& b = points[pick(rng)];
    const Eigen::Vector3d& c = points[pick(rng)];
    Eigen::Vector3d up = (b - a).cross(c - a);
    if (up.norm() < 1e-9) continue;
    up.normalize();
    if (up.z() < 0) up = -up;
    if (up.z() < min_up_z) continue;
    const double height = up.dot(-a);  // the sensor (origin) above the plane
    if (height < kMinHeight) continue;
    size_t inliers = 0;
    for (const Eigen::Vector3d& p : points) inliers += std::abs(up.dot(p) + height) < kInlierDistance;
    if (inliers > best.inliers) best = {true, up, height, inliers};
  }
  if (!best.found) return best;
  // Least squares on the inliers: the plane through their centroid across their thinnest axis.
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  std::vector<Eigen::Vector3d> inliers;
  for (const Eigen::Vector3d& p : points)
    if (std::abs(best.up.dot(p) + best.height) < kInlierDistance) inliers.push_back(p);
  for (const Eigen::Vector3d& p : inliers) centroid += p;
  centroid /= double(inliers.size());
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  for (const Eigen::Vector3d& p : inliers) scatter += (p - centroid) * (p - centroid).transpose();
  Eigen::Vector3d up = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(scatter).eigenvectors().col(0);
  if (up.dot(best.up) < 0) up = -up;
  best.up = up.normalized();
  best.height = best.up.dot(-centroid);
  return best;
}

}  // namespace ndtom
