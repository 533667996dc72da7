#include "loop_closure.h"

#include <chrono>
#include <cmath>
#include <stdexcept>

#include "ndtom_apps/process_clock.h"

namespace ndtom::slam {
namespace {

Matrix6d diagonal(double sigma_m, double sigma_rad) {
  Matrix6d c = Matrix6d::Zero();
  c.diagonal() << Eigen::Vector3d::Constant(sigma_m * sigma_m),
      Eigen::Vector3d::Constant(sigma_rad * sigma_rad);
  return c;
}

}  // namespace

void validate(const LoopClosureOptions& o) {
  validate(o.keyframes);
  validate(o.search);
  validate(o.check);
  if (o.restart_after_lost < 1)
    throw std::invalid_argument(
        "loop restart_after_lost = " + std::to_string(o.restart_after_lost) + ": must be >= 1");
  if (!(o.restart_sigma_m > 0 && o.restart_sigma_deg > 0))
    throw std::invalid_argument("loop restart sigmas: must be > 0");
  if (o.window < 2)
    throw std::invalid_argument("loop window = " + std::to_string(o.window) + ": must be >= 2");
  for (const double v : {o.odometry_sigma_m, o.odometry_sigma_m_per_m, o.odometry_sigma_deg,
                         o.odometry_sigma_deg_per_m})
    if (!(v >= 0 && std::isfinite(v)))
      throw std::invalid_argument("loop odometry sigma: must be finite and >= 0");
  if (o.odometry_sigma_m <= 0 || o.odometry_sigma_deg <= 0)
    throw std::invalid_argument("loop odometry sigma: the constant parts must be > 0");
}

LoopClosure::LoopClosure(const LoopClosureOptions& options, const MapOptions& map, int threads)
    : options_(options), map_options_(map), scan_options_(map.scan), checker_(options.check) {
  validate(options_);
  scan_options_.threads = threads;
}

void LoopClosure::commit(OnlineMapper& mapper, OnlineStep& step,
                         const std::vector<Eigen::Vector3d>& points_sensor,
                         const std::vector<Eigen::Vector3d>& points_map,
                         const Eigen::Vector3d& origin_map) {
  if (!scan_odometry_.empty())
    path_ += (scan_odometry_.back().translation() - step.pose.translation()).norm();
  lost_in_a_row_ = step.outcome == OnlineOutcome::Lost ? lost_in_a_row_ + 1 : 0;
  // Only once the live map is a window: before, it holds every scan, as without loop closure.
  const bool restart =
      lost_in_a_row_ >= options_.restart_after_lost && keyframes_.size() >= options_.window;
  if (restart) {  // placed and inserted at its prediction: the map follows the robot again
    step.outcome = OnlineOutcome::First;
    step.found_by = "restart after lost scans";
    lost_in_a_row_ = 0;
    ++report_.restarts;
  }
  const bool placed = step.outcome != OnlineOutcome::Lost;
  std::optional<Eigen::Isometry3d> change;
  if (keyframes_.empty() || restart ||
      (placed && startsKeyframe(options_.keyframes, keyframes_.back().anchor, step.pose)))
    change = startKeyframe(mapper, step, points_sensor, restart);
  if (!change) {
    finishScan(mapper, step, points_map, origin_map, restart);
    return;
  }
  std::vector<Eigen::Vector3d> moved;  // the scan joins the corrected map
  moved.reserve(points_map.size());
  for (const Eigen::Vector3d& p : points_map) moved.push_back(*change * p);
  finishScan(mapper, step, moved, *change * origin_map, restart);
}

void LoopClosure::finishScan(OnlineMapper& mapper, OnlineStep& step,
                             const std::vector<Eigen::Vector3d>& points_map,
                             const Eigen::Vector3d& origin_map, bool restart) {
  mapper.commit(step, points_map, origin_map);
  scan_keyframe_.push_back(keyframes_.size() - 1);
  scan_odometry_.push_back(step.pose);
  const bool searched =
      step.outcome == OnlineOutcome::Recovered || step.outcome == OnlineOutcome::Lost || restart;
  if (searched && scan_odometry_.size() > 1) {
    keyframes_.back().consistent = false;
    segment_covariance_ +=
        diagonal(options_.recovered_sigma_m, options_.recovered_sigma_deg * M_PI / 180);
  }
  if (!step.inserted) return;
  Keyframe& k = keyframes_.back();
  k.submap.insertScan(points_map, origin_map, scan_options_);
  window_scans_[keyframes_.size() - 1].push_back({points_map, origin_map});
  ++k.scans;
  if (step.outcome != OnlineOutcome::First)
    segment_covariance_ +=
        covarianceInPoseFrame(step.registration.covariance, k.anchor.inverse() * step.pose);
}

std::optional<Eigen::Isometry3d> LoopClosure::startKeyframe(
    OnlineMapper& mapper, OnlineStep& step, const std::vector<Eigen::Vector3d>& points_sensor,
    bool restart) {
  const size_t id = keyframes_.size();
  // Odometry's motion from the last keyframe, in the frame it was measured in.
  const Eigen::Isometry3d relative =
      id > 0 ? keyframes_[id - 1].anchor.inverse() * step.pose : Eigen::Isometry3d::Identity();
  // Its submap is complete now; a loop closed moves the live map where the graph puts it.
  std::optional<Eigen::Isometry3d> change;
  if (id > 0 && checkLoops(id - 1)) {
    change = moveWindow(id);
    step.pose = *change * step.pose;
    step.prediction = *change * step.prediction;
    live_from_odometry_ = *change * live_from_odometry_;
  }
  Keyframe k(map_options_);
  k.first_scan = scan_odometry_.size();
  k.anchor = step.pose;
  k.path_length = path_;
  k.anchor_scan = points_sensor;
  keyframes_.push_back(std::move(k));
  report_.anchors_odometry.push_back(odometryPose(step.pose));
  report_.keyframe_first_scan.push_back(keyframes_.back().first_scan);
  // The graph puts the last keyframe where its anchor is (moveWindow keeps it so).
  graph_.addNode(step.pose);
  if (id == 0) return change;
  addOdometryEdge(id, relative, restart);
  const auto start = std::chrono::steady_clock::now();
  mapper.replaceMap(window(), change.value_or(Eigen::Isometry3d::Identity()));
  if (id >= options_.window) {  // left the window
    coarsen(keyframes_[id - options_.window]);
    window_scans_.erase(id - options_.window);
  }
  report_.window_seconds += apps::secondsSince(start);
  return change;
}

// The finished keyframes of the next window (their submaps, anchors and scans' poses) moved
// by where the graph now puts the newest of them: the live map, and odometry, go on in the
// graph's frame. One motion for all, so the window stays as odometry made it: moved each to
// its own node, its submaps would meet at a kink where the graph spread the loop's error.
// The submaps are their scans inserted again at the moved poses, the exact NDT-OM: moving the
// submaps themselves (movedMap) merges Gaussians that meet in a cell and resamples occupancy,
// and on four 2 km noisy drives odometry after the closures drifted more (doc/slam.md).
Eigen::Isometry3d LoopClosure::moveWindow(size_t id) {
  const auto start = std::chrono::steady_clock::now();
  const Eigen::Isometry3d change = graph_.pose(id - 1) * keyframes_[id - 1].anchor.inverse();
  const size_t begin = id >= options_.window - 1 ? id - (options_.window - 1) : 0;
  for (size_t i = begin; i < id; ++i) {
    Keyframe& k = keyframes_[i];
    NdtMap moved(map_options_);
    for (InsertedScan& s : window_scans_[i]) {
      for (Eigen::Vector3d& p : s.points) p = change * p;
      s.origin = change * s.origin;
      moved.insertScan(s.points, s.origin, scan_options_);
    }
    k.submap = std::move(moved);
    k.anchor = change * k.anchor;
    for (size_t s = k.first_scan; s < scan_odometry_.size() && scan_keyframe_[s] == i; ++s)
      scan_odometry_[s] = change * scan_odometry_[s];
  }
  ++report_.live_corrections;
  report_.correction_seconds += apps::secondsSince(start);
  return change;
}

void LoopClosure::addOdometryEdge(size_t newer, const Eigen::Isometry3d& relative, bool restart) {
  const double d = relative.translation().norm();
  const double deg = options_.odometry_sigma_deg + options_.odometry_sigma_deg_per_m * d;
  const Matrix6d model =
      restart ? diagonal(options_.restart_sigma_m, options_.restart_sigma_deg * M_PI / 180)
              : diagonal(options_.odometry_sigma_m + options_.odometry_sigma_m_per_m * d,
                         deg * M_PI / 180);
  graph_.addEdge(newer - 1, newer, relative, model + segment_covariance_);
  segment_covariance_.setZero();
}

// The finished keyframes of the window, merged (RCU): the live map of the next keyframe.
NdtMap LoopClosure::window() const {
  const size_t end = keyframes_.size() - 1;  // the new one is still empty
  const size_t begin = end >= options_.window - 1 ? end - (options_.window - 1) : 0;
  NdtMap live = keyframes_[end - 1].submap;  // a copy costs less than a merge
  for (size_t i = begin; i + 1 < end; ++i) live.merge(keyframes_[i].submap);
  return live;
}

// Loop checks register on submaps of twice the map's cell (the online mapper's finest
// level): the old ones are kept so (an eighth of the memory), the newest is coarsened for
// its check. Keyframes still in the live window stay fine and are never candidates.
void LoopClosure::coarsen(Keyframe& k) const {
  if (k.submap.options().resolution == map_options_.resolution) k.submap = k.submap.coarsened(2);
}

bool LoopClosure::checkLoops(size_t current) {
  if (!keyframes_[current].consistent) return false;
  std::vector<KeyframePlace> places;
  for (size_t i = 0; i <= current; ++i)
    places.push_back({graph_.pose(i).translation(), keyframes_[i].path_length});
  const double radius =
      loopSearchRadius(options_.search, keyframes_[current].path_length - path_at_closure_);
  std::vector<size_t> candidates;
  // A submap spans a keyframe's length: anchors that far apart still overlap.
  const double reach = radius + options_.keyframes.distance;
  for (const size_t older : loopCandidates(options_.search, places, current, reach))
    if (older + options_.window <= current && keyframes_[older].consistent)
      candidates.push_back(older);
  if (candidates.empty()) return false;
  Keyframe newer = keyframes_[current];
  coarsen(newer);
  bool closed = false;
  for (const size_t older : candidates) {
    coarsen(keyframes_[older]);
    closed |= checkLoop(older, current, newer, radius);
  }
  if (closed) {
    optimize();
    path_at_closure_ = keyframes_[current].path_length;
  }
  return closed;
}

bool LoopClosure::checkLoop(size_t older, size_t current, const Keyframe& newer, double radius) {
  const auto start = std::chrono::steady_clock::now();
  const Eigen::Isometry3d guess = graph_.pose(older).inverse() * graph_.pose(current);
  LoopRecord record{
      older, current,
      checker_.check(keyframes_[older], newer, guess, radius, options_.search.max_local_radius)};
  report_.check_seconds += apps::secondsSince(start);
  record.check.forward.levels.clear();
  record.check.backward.levels.clear();
  const bool accepted = record.check.accepted;
  if (accepted) graph_.addEdge(older, current, record.check.relative, record.check.covariance);
  ++(accepted ? report_.accepted : report_.rejected);
  report_.loops.push_back(std::move(record));
  return accepted;
}

void LoopClosure::optimize() {
  report_.last_optimization = graph_.optimize();
  report_.optimize_seconds += report_.last_optimization.seconds;
  ++report_.optimizations;
}

void LoopClosure::finish() {
  if (keyframes_.empty()) return;
  checkLoops(keyframes_.size() - 1);
  if (report_.accepted > 0) optimize();
  report_.anchors_optimized.clear();
  for (size_t i = 0; i < keyframes_.size(); ++i)
    report_.anchors_optimized.push_back(graph_.pose(i));
  report_.graph_text = graph_.text();
}

Eigen::Isometry3d LoopClosure::optimizedPose(size_t index) const {
  const size_t k = scan_keyframe_.at(index);
  return graph_.pose(k) * keyframes_[k].anchor.inverse() * scan_odometry_[index];
}

}  // namespace ndtom::slam
