#include "slam_loop.h"

#include <chrono>
#include <cstdio>

#include "ndtom/map/memory_budget.h"
#include "ndtom_apps/process_clock.h"
#include "ndtom_io/pose_file.h"

namespace ndtom::slam {

size_t SlamResult::count(ndtom::OnlineOutcome outcome) const {
  size_t n = 0;
  for (const SlamScan& s : scans) n += s.step.outcome == outcome;
  return n;
}

std::string tumLine(double time, const Eigen::Isometry3d& pose, Eigen::Isometry3d* as_read) {
  const Eigen::Vector3d t = pose.translation();
  const Eigen::Quaterniond q(pose.linear());
  char line[256];
  std::snprintf(line, sizeof(line), "%.9f %.17g %.17g %.17g %.17g %.17g %.17g %.17g", time, t.x(),
                t.y(), t.z(), q.x(), q.y(), q.z(), q.w());
  // %.17g reads back as the same doubles: the pose is what the reader makes of them.
  const double translation[3] = {t.x(), t.y(), t.z()};
  *as_read = ndtom::io::poseFromTranslationQuaternion(translation, q.x(), q.y(), q.z(), q.w());
  return line;
}

namespace {

// Each scan at its optimized pose, rounded to what PREFIX.tum holds.
void useOptimizedPoses(const LoopClosure& closure, SlamResult& out) {
  for (size_t i = 0; i < out.scans.size(); ++i) {
    SlamScan& s = out.scans[i];
    s.tum_line = tumLine(s.step.time, closure.optimizedPose(i), &s.step.pose);
  }
}

}  // namespace

SlamResult runOnline(apps::ScanSource& source, const ndtom::OnlineMapperOptions& options,
                     const LoopClosureOptions& loops, apps::Progress& progress) {
  const auto start = std::chrono::steady_clock::now();
  SlamResult out;
  ndtom::OnlineMapper mapper(options);
  std::optional<LoopClosure> closure;
  if (loops.enabled) closure.emplace(loops, options.map, options.threads);
  std::optional<Eigen::Isometry3d> last_odometry;
  size_t points_done = 0;
  progress.start("mapping", source.size());
  while (auto scan = source.next()) {
    SlamScan record;
    record.name = scan->name;
    record.points = scan->points_world.size();
    std::optional<Eigen::Isometry3d> odometry;
    if (scan->pose_kind == apps::Scan::PoseKind::Odometry) {
      if (last_odometry) odometry = last_odometry->inverse() * scan->frame_pose;
      last_odometry = scan->frame_pose;
      out.odometry_used = true;
    }
    try {
      const std::vector<Eigen::Vector3d> points = apps::pointsInFrame(*scan);
      record.step = mapper.locate(points, scan->time, odometry);
      record.tum_line = tumLine(scan->time, record.step.pose, &record.step.pose);
      apps::placeAt(*scan, record.step.pose);
      if (closure)
        closure->commit(mapper, record.step, points, scan->points_world, scan->sensor_origin);
      else
        mapper.commit(record.step, scan->points_world, scan->sensor_origin);
      record.live = record.step.pose;
      record.odometry = closure ? closure->odometryPose(record.live) : record.live;
    } catch (const ndtom::MemoryBudgetError& e) {
      throw apps::InputError(scan->name + ": " + e.what());
    } catch (const std::invalid_argument& e) {
      throw apps::InputError(scan->name + ": " + e.what());
    }
    if (record.step.inserted) {
      out.points += record.step.insertion;
      out.sensor_path.push_back(scan->sensor_origin);
    }
    points_done += record.points;
    out.scans.push_back(std::move(record));
    progress.update(out.scans.size(), points_done);
  }
  progress.finish();
  out.skips = source.skips();
  out.map = mapper.takeMap();
  if (closure) {
    closure->finish();
    useOptimizedPoses(*closure, out);
    out.loops = closure->report();
  }
  out.seconds = apps::secondsSince(start);
  return out;
}

void rebuildAtOptimizedPoses(apps::ScanSource& source, const ndtom::OnlineMapperOptions& options,
                             SlamResult& result, apps::Progress& progress) {
  const auto start = std::chrono::steady_clock::now();
  ndtom::NdtMap map(options.map);
  ScanOptions scan_options = options.map.scan;
  scan_options.threads = options.threads;
  result.points = {};
  result.sensor_path.clear();
  size_t i = 0, points_done = 0;
  progress.start("rebuilding at the optimized poses", result.scans.size());
  while (auto scan = source.next()) {
    if (i >= result.scans.size())
      throw apps::InputError("the input gave more scans when read again");
    SlamScan& s = result.scans[i++];
    points_done += scan->points_world.size();
    if (s.step.inserted) {
      apps::placeAt(*scan, s.step.pose);
      try {
        result.points += map.insertScan(scan->points_world, scan->sensor_origin, scan_options);
      } catch (const ndtom::MemoryBudgetError& e) {
        throw apps::InputError(scan->name + ": " + e.what());
      }
      result.sensor_path.push_back(scan->sensor_origin);
    }
    progress.update(i, points_done);
  }
  progress.finish();
  if (i != result.scans.size())
    throw apps::InputError("the input gave fewer scans when read again");
  result.map = std::move(map);
  result.rebuild_seconds = apps::secondsSince(start);
}

}  // namespace ndtom::slam
