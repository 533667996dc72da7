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
  bool city_size_given = false;        ///< else sized from the route's length
  std::optional<uint64_t> noise_seed;  ///< --noise-seed: the lidar's alone
  RouteSettings route;
  LidarModel lidar;
  double speed = 10;  ///< (m/s) for times.txt
  int threads = 1;
  bool threads_given = false;  ///< else as many as the machine's cores the budget holds
  uint64_t memory_budget = 0;  ///< (bytes) --memory-budget; ndtom-map's default
  bool quiet = false, help = false;
};

/// Bytes one scan of `lidar` takes while it is simulated and written (its points, at most
/// one a ray, as they grow): what each thread holds.
uint64_t scanBytes(const LidarModel& lidar);
/// Bytes the scan files of a run take on disk: a header and 12 bytes a point, about half
/// the rays hitting something (the ground alone takes the rings below the horizon).
uint64_t scanFileBytes(const LidarModel& lidar, uint64_t scans);

/// Bytes a run holds at most: the city, the route, and each thread's scan.
uint64_t runBytes(const WorldOptions& o);

/// Throws apps::UsageError, naming the options and the figures, unless the scan files fit
/// the free space of the disk that will hold `o.out` (checked before anything is written).
void checkDiskSpace(const WorldOptions& o);

/// Throws apps::UsageError naming the option for a bad command line, and for a run over the
/// limits: more than kMaxRouteScans scans, or more memory than the budget (the city's blocks,
/// the scans' rays times the threads).
WorldOptions parseWorldOptions(int argc, const char* const argv[]);
std::string worldHelpText();

/// Blocks per side of a square city in which a drive of `length` metres mostly meets new
/// streets (twice the street length it drives).
int blocksForRoute(double length, double block_pitch);

}  // namespace ndtom::world
