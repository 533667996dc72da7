#include "synthetic_scans.h"

#include <Eigen/Geometry>
#include <cmath>
#include <limits>
#include <random>

namespace ndtom::bench {

namespace {

constexpr double kPi = 3.14159265358979323846;

struct Aabb {
  Eigen::Vector3d lo, hi;
};

/// The yard: 80 m × 60 m inside 8 m walls; obstacles stay clear of the loop driven below
/// (the rectangle |x| = 20 m, |y| = 12 m).
std::vector<Aabb> yardScene() {
  auto box = [](double x, double y, double sx, double sy, double h) {
    return Aabb{{x - sx / 2, y - sy / 2, 0.0}, {x + sx / 2, y + sy / 2, h}};
  };
  return {
      box(0, 30.25, 80.5, 0.5, 8), box(0, -30.25, 80.5, 0.5, 8),  // walls
      box(40.25, 0, 0.5, 60, 8),   box(-40.25, 0, 0.5, 60, 8),    //
      box(-8, 4, 4.5, 1.8, 1.5),   box(-2, 4, 4.5, 1.8, 1.5),     // parked cars
      box(4, 4, 4.5, 1.8, 1.5),    box(10, -5, 4.5, 1.8, 1.5),    //
      box(-30, 20, 6, 2.5, 2.6),   box(30, -22, 2.5, 6, 2.6),     // containers
      box(28, 18, 12, 2.5, 2.6),   box(-28, -20, 2.5, 12, 5.2),   //
      box(-12, -4, 3, 3, 1.0),     box(0, -3, 2, 2, 2.0),         // crates
      box(-20, 20, 0.4, 0.4, 4),   box(20, 20, 0.4, 0.4, 4),      // pillars
      box(-20, -20, 0.4, 0.4, 4),  box(20, -20, 0.4, 0.4, 4),     //
      box(0, 20, 0.4, 0.4, 4),     box(0, -20, 0.4, 0.4, 4),      //
      box(-34, 0, 6, 10, 3.5),     box(34, 6, 4, 4, 6.0),         // sheds
  };
}

/// Distance along unit direction `d` from `o` to the nearest surface (ground or box).
double castRay(const std::vector<Aabb>& scene, const Eigen::Vector3d& o, const Eigen::Vector3d& d) {
  double best = d.z() < 0 ? -o.z() / d.z() : std::numeric_limits<double>::infinity();
  const Eigen::Vector3d inv = d.cwiseInverse();
  for (const Aabb& b : scene) {  // slab test
    double t_in = 0, t_out = best;
    for (int a = 0; a < 3; ++a) {
      double t0 = (b.lo[a] - o[a]) * inv[a], t1 = (b.hi[a] - o[a]) * inv[a];
      if (t0 > t1) std::swap(t0, t1);
      t_in = std::max(t_in, t0);
      t_out = std::min(t_out, t1);
    }
    if (t_in <= t_out && t_in > 0) best = t_in;
  }
  return best;
}

/// Pose at arc length s on the loop: position at sensor height, heading along the path.
Eigen::Isometry3d loopPose(double s) {
  const double hx = 20, hy = 12, perimeter = 4 * (hx + hy);
  s = std::fmod(s, perimeter);
  Eigen::Vector2d p, dir;
  if (s < 2 * hx) {
    p = {-hx + s, -hy}, dir = {1, 0};
  } else if (s < 2 * hx + 2 * hy) {
    p = {hx, -hy + (s - 2 * hx)}, dir = {0, 1};
  } else if (s < 4 * hx + 2 * hy) {
    p = {hx - (s - 2 * hx - 2 * hy), hy}, dir = {-1, 0};
  } else {
    p = {-hx, hy - (s - 4 * hx - 2 * hy)}, dir = {0, -1};
  }
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation() = Eigen::Vector3d(p.x(), p.y(), SyntheticLidar::kHeight);
  pose.linear() =
      Eigen::AngleAxisd(std::atan2(dir.y(), dir.x()), Eigen::Vector3d::UnitZ()).toRotationMatrix();
  return pose;
}

Scan spinOnce(const std::vector<Aabb>& scene, const Eigen::Isometry3d& pose, std::mt19937& rng) {
  using L = SyntheticLidar;
  std::normal_distribution<double> noise(0.0, L::kRangeNoise);
  Scan scan;
  scan.origin = pose.translation();
  scan.pose = pose;
  scan.points.reserve(L::kRings * L::kAzimuthSteps);
  for (int ring = 0; ring < L::kRings; ++ring) {
    const double elevation = (L::kElevationLowDeg + (L::kElevationTopDeg - L::kElevationLowDeg) *
                                                        ring / (L::kRings - 1)) *
                             kPi / 180;
    for (int k = 0; k < L::kAzimuthSteps; ++k) {
      const double azimuth = 2 * kPi * k / L::kAzimuthSteps;
      const Eigen::Vector3d local(std::cos(elevation) * std::cos(azimuth),
                                  std::cos(elevation) * std::sin(azimuth), std::sin(elevation));
      const Eigen::Vector3d d = pose.linear() * local;
      const double range = castRay(scene, scan.origin, d) + noise(rng);
      scan.points.push_back(scan.origin + range * d);
    }
  }
  return scan;
}

}  // namespace

ScanSet generateSyntheticScans(int num_scans) {
  const std::vector<Aabb> scene = yardScene();
  std::mt19937 rng(20130101);
  ScanSet set;
  set.name = "synthetic";
  for (int i = 0; i < num_scans; ++i)
    set.scans.push_back(spinOnce(scene, loopPose(i * SyntheticLidar::kStep), rng));
  return set;
}

}  // namespace ndtom::bench
