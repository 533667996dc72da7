// ndtom-worldgen's command line.
#pragma once

#include <optional>
#include <string>

#include "city_route.h"
#include "simulated_lidar.h"

namespace ndtom::world {

struct WorldOptions {
  std::string out;  ///< folder for the scans, poses.txt and times.txt
  CityLayout city;
  bool city_size_given = false;  ///< else sized from the route's length
  std::optional<uint64_t> noise_seed;  ///< --noise-seed: the lidar's alone
  RouteSettings route;
  LidarModel lidar;
  double speed = 10;  ///< (m/s) for times.txt
  int threads = 1;
  bool quiet = false, help = false;
};

/// Throws apps::UsageError naming the option for a bad command line.
WorldOptions parseWorldOptions(int argc, const char* const argv[]);
std::string worldHelpText();

/// Blocks per side of a square city in which a drive of `length` metres mostly meets new
/// streets (twice the street length it drives).
int blocksForRoute(double length, double block_pitch);

}  // namespace ndtom::world
