#include "city_route.h"

#include <cmath>
#include <map>
#include <random>
#include <stdexcept>

namespace ndtom::world {

std::vector<Eigen::Isometry3d> driveThrough(const CityWorld& city, const RouteSettings& r) {
  if (!(r.length > 0) || !(r.step > 0) || !(r.length / r.step < 1e7))
    throw std::invalid_argument("route: length and step must be positive, at most 1e7 steps");
  const CityLayout& l = city.layout();
  // Crossings (i, j) at (i, j) · pitch, 0 ≤ i ≤ blocks_x, 0 ≤ j ≤ blocks_y.
  const Eigen::Vector2i directions[4] = {{1, 0}, {0, 1}, {-1, 0}, {0, -1}};
  std::map<std::pair<int, int>, int> driven;  // times each street segment was driven
  const auto segment = [](Eigen::Vector2i a, Eigen::Vector2i b) {
    const int ka = a.x() * 100003 + a.y(), kb = b.x() * 100003 + b.y();
    return std::make_pair(std::min(ka, kb), std::max(ka, kb));
  };
  std::mt19937_64 rng(r.seed);
  Eigen::Vector2i at(0, 0);
  int heading = 0;
  std::vector<Eigen::Isometry3d> poses;
  const size_t count = size_t(std::floor(r.length / r.step)) + 1;
  double carried = 0;  // metres into the current segment where the next pose falls
  while (poses.size() < count) {
    // The least-driven street ahead, left or right; ties broken at random.
    int best = -1, best_driven = 0;
    for (const int turn : {0, 1, 3}) {
      const int h = (heading + turn) % 4;
      const Eigen::Vector2i next = at + directions[h];
      if (next.x() < 0 || next.y() < 0 || next.x() > l.blocks_x || next.y() > l.blocks_y)
        continue;
      const int times = driven[segment(at, next)];
      if (best < 0 || times < best_driven || (times == best_driven && rng() % 2 == 0))
        best = h, best_driven = times;
    }
    if (best < 0) best = (heading + 2) % 4;  // a dead end (a 1-block-wide city): turn back
    const Eigen::Vector2i next = at + directions[best];
    ++driven[segment(at, next)];
    const Eigen::Vector2d a = at.cast<double>() * l.block_pitch,
                          b = next.cast<double>() * l.block_pitch;
    const double yaw = std::atan2(b.y() - a.y(), b.x() - a.x());
    for (double s = carried; s < l.block_pitch && poses.size() < count; s += r.step) {
      const Eigen::Vector2d p = a + (b - a) * (s / l.block_pitch);
      Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
      pose.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
      pose.translation() = Eigen::Vector3d(p.x(), p.y(), r.sensor_height);
      poses.push_back(pose);
      carried = s + r.step - l.block_pitch;
    }
    at = next;
    heading = best;
  }
  return poses;
}

}  // namespace ndtom::world
