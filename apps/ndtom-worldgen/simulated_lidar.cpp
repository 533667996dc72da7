#include "simulated_lidar.h"

#include <cmath>
#include <random>

namespace ndtom::world {

std::vector<Eigen::Vector3d> simulateScan(const CityWorld& city, const LidarModel& m,
                                          const Eigen::Isometry3d& pose, uint64_t scan_index) {
  std::mt19937_64 rng(m.seed * 0x9E3779B97F4A7C15ull + scan_index);
  // Box-Muller from the raw generator: the same numbers with every standard library.
  const auto normal = [&rng] {
    const double u1 = (double(rng() >> 11) + 1) * 0x1.0p-53, u2 = double(rng() >> 11) * 0x1.0p-53;
    return std::sqrt(-2 * std::log(u1)) * std::cos(2 * M_PI * u2);
  };
  std::vector<Eigen::Vector3d> points;
  points.reserve(size_t(m.rings) * size_t(m.azimuth_steps) / 2);
  const Eigen::Vector3d origin = pose.translation();
  for (int ring = 0; ring < m.rings; ++ring) {
    const double elevation =
        (m.rings == 1 ? m.elevation_low_deg
                      : m.elevation_low_deg + (m.elevation_top_deg - m.elevation_low_deg) * ring /
                                                  (m.rings - 1)) *
        M_PI / 180;
    for (int k = 0; k < m.azimuth_steps; ++k) {
      const double azimuth = 2 * M_PI * k / m.azimuth_steps;
      const Eigen::Vector3d local(std::cos(elevation) * std::cos(azimuth),
                                  std::cos(elevation) * std::sin(azimuth), std::sin(elevation));
      const double noise = m.range_noise * normal();  // drawn for every ray: stable streams
      const auto range = city.castRay(origin, pose.linear() * local, m.max_range);
      if (!range) continue;
      points.push_back(local * std::max(0.0, *range + noise));
    }
  }
  return points;
}

}  // namespace ndtom::world
