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

}  // namespace

uint64_t routeScans(double length, double step) {
  const double scans = std::floor(length / step) + 1;
  return scans < 1.8e19 ? uint64_t(scans) : UINT64_MAX;
}

uint64_t routeBytes(const CityLayout& city, const RouteSettings& route) {
  // Crossings: 1.1 × length / pitch + 3, 8 bytes each, twice while their vector grows; the
  // streets driven: a map node (~64 bytes) for each crossing at most.
  const double crossings = 1.1 * route.length / city.block_pitch + 3;
  const double bytes = crossings * (2 * sizeof(Eigen::Vector2i) + 64);
  return bytes < 1.8e19 ? uint64_t(bytes) : UINT64_MAX;
}

Drive::Drive(const CityWorld& city, const RouteSettings& r) : route_(r) {
  if (!(r.length > 0) || !(r.step > 0) || routeScans(r.length, r.step) > kMaxRouteScans)
    throw std::invalid_argument("route: length and step must be positive, at most " +
                                std::to_string(kMaxRouteScans) + " scans");
  const CityLayout& l = city.layout();
  if (r.margin < 0 || 2 * r.margin >= std::min(l.blocks_x, l.blocks_y))
    throw std::invalid_argument("route: the margin must leave at least one block inside");
  pitch_ = l.block_pitch;
  crossings_ = crossingsFor(l, r.length, r.seed, r.margin);
  from_ = crossings_[0].cast<double>() * pitch_;
  count_ = routeScans(r.length, r.step);
}

void Drive::line(Eigen::Vector2d a, Eigen::Vector2d b) {
  const double length = (b - a).norm();
  const double yaw = std::atan2(b.y() - a.y(), b.x() - a.x());
  double s = carried_;
  for (; s < length; s += route_.step) samples_.push_back({a + (b - a) * (s / length), yaw});
  carried_ = s - length;
}

void Drive::arc(Eigen::Vector2d centre, double start_angle, double turn) {
  const double length = std::abs(turn) * kTurnRadius;
  double s = carried_;
  for (; s < length; s += route_.step) {
    const double angle = start_angle + turn * (s / length);
    samples_.push_back({centre + kTurnRadius * Eigen::Vector2d(std::cos(angle), std::sin(angle)),
                        angle + (turn > 0 ? M_PI / 2 : -M_PI / 2)});
  }
  carried_ = s - length;
}

// The centre lines through the crossings, each turn a quarter circle (a U-turn at a dead end
// is left sharp), sampled every step metres of arc length: one corner's pieces at a time.
void Drive::samplePiece() {
  const size_t i = corner_++;
  const Eigen::Vector2d corner = crossings_[i].cast<double>() * pitch_;
  const Eigen::Vector2d in = (corner - crossings_[i - 1].cast<double>() * pitch_).normalized();
  const Eigen::Vector2d out_dir = (crossings_[i + 1].cast<double>() * pitch_ - corner).normalized();
  const double cross = in.x() * out_dir.y() - in.y() * out_dir.x();
  if (std::abs(cross) < 0.5) {  // straight on, or back
    line(from_, corner);
    from_ = corner;
    return;
  }
  const Eigen::Vector2d enter = corner - kTurnRadius * in, leave = corner + kTurnRadius * out_dir;
  line(from_, enter);
  const Eigen::Vector2d centre =
      enter + kTurnRadius *
                  (cross > 0 ? Eigen::Vector2d(-in.y(), in.x()) : Eigen::Vector2d(in.y(), -in.x()));
  const Eigen::Vector2d radial = enter - centre;
  arc(centre, std::atan2(radial.y(), radial.x()), cross > 0 ? M_PI / 2 : -M_PI / 2);
  from_ = leave;
}

bool Drive::next(Eigen::Isometry3d& pose) {
  if (given_ >= count_) return false;
  while (samples_.empty() && corner_ + 1 < crossings_.size()) samplePiece();
  if (samples_.empty()) return false;
  const PathPoint p = samples_.front();
  samples_.pop_front();
  ++given_;
  pose = Eigen::Isometry3d::Identity();
  pose.linear() = Eigen::AngleAxisd(p.yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  pose.translation() = Eigen::Vector3d(p.position.x(), p.position.y(), route_.sensor_height);
  return true;
}

std::vector<Eigen::Isometry3d> driveThrough(const CityWorld& city, const RouteSettings& r) {
  Drive drive(city, r);
  std::vector<Eigen::Isometry3d> poses;
  for (Eigen::Isometry3d pose; drive.next(pose);) poses.push_back(pose);
  return poses;
}

}  // namespace ndtom::world
