// A synthetic room for the likelihood and registration tests: floor, four walls and a box,
// sampled at random with 1 cm noise, seen from a sensor 1.5 m above the floor. Its planes
// constrain all six degrees of freedom.
#pragma once

#include <Eigen/Core>
#include <random>
#include <vector>

#include "ndtom/map/ndt_map.h"

namespace ndtom::testing {

inline const Eigen::Vector3d kRoomSensor(0.3, -0.2, 1.5);

/// `n` points on the room's surfaces (world frame, metres), reproducible from `seed`.
inline std::vector<Eigen::Vector3d> sampleRoom(size_t n, unsigned seed, double noise = 0.01) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::normal_distribution<double> e(0.0, noise);
  std::vector<Eigen::Vector3d> points;
  points.reserve(n);
  for (size_t i = 0; i < n; ++i) {
    const double a = u(rng), b = u(rng);
    switch (i % 7) {
      case 0:
      case 1:
        points.emplace_back(-4 + 8 * a, -3 + 6 * b, e(rng));  // floor, 8 x 6 m
        break;
      case 2:
        points.emplace_back(4 + e(rng), -3 + 6 * a, 2.5 * b);  // wall x = 4
        break;
      case 3:
        points.emplace_back(-4 + e(rng), -3 + 6 * a, 2.5 * b);  // wall x = -4
        break;
      case 4:
        points.emplace_back(-4 + 8 * a, 3 + e(rng), 2.5 * b);  // wall y = 3
        break;
      case 5:
        points.emplace_back(-4 + 8 * a, -3 + e(rng), 2.5 * b);  // wall y = -3
        break;
      default:  // top and one side of a 1 x 1 x 0.8 m box
        if (u(rng) < 0.5)
          points.emplace_back(1 + a, 0.5 + b, 0.8 + e(rng));
        else
          points.emplace_back(1 + e(rng), 0.5 + a, 0.8 * b);
        break;
    }
  }
  return points;
}

/// A map of one scan of `n` room points (seed 1) from kRoomSensor, in `resolution` m cells.
inline NdtMap roomMap(double resolution, size_t n) {
  MapOptions options;
  options.resolution = resolution;
  NdtMap map(options);
  map.insertScan(sampleRoom(n, 1), kRoomSensor);
  return map;
}

}  // namespace ndtom::testing
