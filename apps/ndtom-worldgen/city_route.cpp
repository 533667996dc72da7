#include "city_route.h"

#include <cmath>
#include <map>
#include <random>
#include <stdexcept>

namespace ndtom::world {
namespace {

constexpr double kTurnRadius = 8.0;  // m: corners are quarter circles, as a car drives them

// The crossings the drive passes, in order: at each, the least-driven street ahead, left or
// right (never back unless at a dead end), ties broken at random; enough for `length` metres.
// Crossings lie in [margin, blocks - margin] on each axis.
std::vector<Eigen::Vector2i> crossingsFor(const CityLayout& l, double length, uint64_t seed,
                                          int margin) {
  const Eigen::Vector2i directions[4] = {{1, 0}, {0, 1}, {-1, 0}, {0, -1}};
  std::map<std::pair<int, int>, int> driven;  // times each street segment was driven
  const auto segment = [](Eigen::Vector2i a, Eigen::Vector2i b) {
    const int ka = a.x() * 100003 + a.y(), kb = b.x() * 100003 + b.y();
    return std::make_pair(std::min(ka, kb), std::max(ka, kb));
  };
  std::mt19937_64 rng(seed);
  std::vector<Eigen::Vector2i> crossings{{margin, margin}};
  int heading = 0;
  // Rounded corners cut at most 2R - πR/2 = 3.4 m a segment (4 % of one): 10 % more, and one
  // segment more, as the last corner is rounded too.
  while (double(crossings.size() - 2) * l.block_pitch < 1.1 * length + l.block_pitch ||
         crossings.size() < 3) {
    const Eigen::Vector2i at = crossings.back();
    int best = -1, best_driven = 0;
    for (const int turn : {0, 1, 3}) {
      const int h = (heading + turn) % 4;
      const Eigen::Vector2i next = at + directions[h];
      if (next.x() < margin || next.y() < margin || next.x() > l.blocks_x - margin ||
          next.y() > l.blocks_y - margin)
        continue;
      const int times = driven[segment(at, next)];
      if (best < 0 || times < best_driven || (times == best_driven && rng() % 2 == 0))
        best = h, best_driven = times;
    }
    if (best < 0) best = (heading + 2) % 4;  // a dead end (a 1-block-wide city): turn back
    ++driven[segment(at, at + directions[best])];
    crossings.push_back(at + directions[best]);
    heading = best;
  }
  return crossings;
}

struct PathPoint {
  Eigen::Vector2d position;
  double yaw;
};

// The centre lines through the crossings, each turn a quarter circle (a U-turn at a dead end
// is left sharp), sampled every `spacing` metres of arc length.
std::vector<PathPoint> smoothPath(const std::vector<Eigen::Vector2i>& crossings, double pitch,
                                  double spacing) {
  std::vector<PathPoint> out;
  double carried = 0;  // arc length into the next piece where the next sample falls
  const auto line = [&](Eigen::Vector2d a, Eigen::Vector2d b) {
    const double length = (b - a).norm();
    const double yaw = std::atan2(b.y() - a.y(), b.x() - a.x());
    double s = carried;
    for (; s < length; s += spacing) out.push_back({a + (b - a) * (s / length), yaw});
    carried = s - length;
  };
  const auto arc = [&](Eigen::Vector2d centre, double start_angle, double turn) {
    const double length = std::abs(turn) * kTurnRadius;
    double s = carried;
    for (; s < length; s += spacing) {
      const double angle = start_angle + turn * (s / length);
      out.push_back({centre + kTurnRadius * Eigen::Vector2d(std::cos(angle), std::sin(angle)),
                     angle + (turn > 0 ? M_PI / 2 : -M_PI / 2)});
    }
    carried = s - length;
  };
  Eigen::Vector2d from = crossings[0].cast<double>() * pitch;
  for (size_t i = 1; i + 1 < crossings.size(); ++i) {
    const Eigen::Vector2d corner = crossings[i].cast<double>() * pitch;
    const Eigen::Vector2d in = (corner - crossings[i - 1].cast<double>() * pitch).normalized();
    const Eigen::Vector2d out_dir = (crossings[i + 1].cast<double>() * pitch - corner).normalized();
    const double cross = in.x() * out_dir.y() - in.y() * out_dir.x();
    if (std::abs(cross) < 0.5) {  // straight on, or back
      line(from, corner);
      from = corner;
      continue;
    }
    const Eigen::Vector2d enter = corner - kTurnRadius * in, leave = corner + kTurnRadius * out_dir;
    line(from, enter);
    const Eigen::Vector2d centre = enter + kTurnRadius * (cross > 0 ? Eigen::Vector2d(-in.y(), in.x())
                                                                   : Eigen::Vector2d(in.y(), -in.x()));
    const Eigen::Vector2d radial = enter - centre;
    arc(centre, std::atan2(radial.y(), radial.x()), cross > 0 ? M_PI / 2 : -M_PI / 2);
    from = leave;
  }
  return out;
}

}  // namespace

std::vector<Eigen::Isometry3d> driveThrough(const CityWorld& city, const RouteSettings& r) {
  if (!(r.length > 0) || !(r.step > 0) || !(r.length / r.step < 1e7))
    throw std::invalid_argument("route: length and step must be positive, at most 1e7 steps");
  const CityLayout& l = city.layout();
  if (r.margin < 0 || 2 * r.margin >= std::min(l.blocks_x, l.blocks_y))
    throw std::invalid_argument("route: the margin must leave at least one block inside");
  const auto path = smoothPath(crossingsFor(l, r.length, r.seed, r.margin), l.block_pitch, r.step);
  const size_t count = size_t(std::floor(r.length / r.step)) + 1;
  std::vector<Eigen::Isometry3d> poses;
  for (size_t i = 0; i < count && i < path.size(); ++i) {
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    pose.linear() = Eigen::AngleAxisd(path[i].yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    pose.translation() = Eigen::Vector3d(path[i].position.x(), path[i].position.y(), r.sensor_height);
    poses.push_back(pose);
  }
  return poses;
}

}  // namespace ndtom::world
