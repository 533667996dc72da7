// A drive through a CityWorld: along the streets' centre lines from one crossing to the next
// (turning on quarter circles of 8 m, as a car does),
// preferring streets not driven yet (so the map grows with the distance, as a survey's does),
// never turning back. Poses every `step` metres, the sensor facing the driving direction.
#pragma once

#include <Eigen/Geometry>
#include <cstdint>
#include <deque>
#include <vector>

#include "city_world.h"

namespace ndtom::world {

struct RouteSettings {
  double length = 2000;        ///< (m) driven
  double step = 1.0;           ///< (m) between scans
  double sensor_height = 1.8;  ///< (m) above the street
  uint64_t seed = 1;
  /// Rings of blocks kept round the driven streets: the drive stays off the outermost
  /// `margin` streets of each side, so every street it drives has city all around.
  int margin = 0;
};

/// Most scans a route may have (floor(length / step) + 1).
inline constexpr uint64_t kMaxRouteScans = 10000000;
/// Scans along a route of `length` and `step`: floor(length / step) + 1 (unchecked).
uint64_t routeScans(double length, double step);
/// Bytes a route holds at most while it is driven (its crossings and the streets driven):
/// they grow with length / block_pitch, not with the scans.
uint64_t routeBytes(const CityLayout& city, const RouteSettings& route);

/// The sensor poses (sensor → world) along the route, one at a time: memory does not grow
/// with the number of poses. Throws std::invalid_argument as driveThrough.
class Drive {
 public:
  Drive(const CityWorld& city, const RouteSettings& route);
  /// Poses at most (routeScans()); the drive may end a pose early.
  uint64_t size() const { return count_; }
  /// The next pose, or false once the drive is over.
  bool next(Eigen::Isometry3d& pose);

 private:
  struct PathPoint {
    Eigen::Vector2d position;
    double yaw;
  };
  void samplePiece();  // the next line or arc of the path into samples_
  void line(Eigen::Vector2d a, Eigen::Vector2d b);
  void arc(Eigen::Vector2d centre, double start_angle, double turn);

  RouteSettings route_;
  double pitch_;
  std::vector<Eigen::Vector2i> crossings_;
  size_t corner_ = 1;        // the next crossing to turn at
  bool last_piece_ = false;  // the final line, to the last corner, was sampled
  Eigen::Vector2d from_;     // where the next piece starts
  double carried_ = 0;       // arc length into the next piece where the next sample falls
  std::deque<PathPoint> samples_;
  uint64_t count_ = 0, given_ = 0;
};

/// Sensor poses (sensor → world) along the route: length / step + 1 of them, starting at the
/// crossing (margin, margin). Throws std::invalid_argument for a non-positive length or step,
/// over kMaxRouteScans poses, or a margin that leaves no block inside. All in memory: tests
/// and small routes (the program drives a Drive).
std::vector<Eigen::Isometry3d> driveThrough(const CityWorld& city, const RouteSettings& route);

}  // namespace ndtom::world
