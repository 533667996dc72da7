// ndtom-slam: maps a log without given poses (online NDT-OM, lidar odometry by scan-to-map
// NDT registration) and writes what ndtom-map writes plus the trajectory. Exit code 0 on
// success, 1 for bad input data or a failed write, 2 for a bad command line.
#include <chrono>
#include <cstdio>

#include "loop_picture.h"
#include "ndtom_apps/map_outputs.h"
#include "ndtom_apps/oblique_view.h"
#include "ndtom_apps/png_bytes.h"
#include "ndtom_apps/process_clock.h"
#include "ndtom_apps/process_memory.h"
#include "ndtom_apps/run_budget.h"
#include "ndtom_apps/run_program.h"
#include "ndtom_apps/settings_from_options.h"
#include "ndtom_apps/trajectory_poses.h"
#include "slam_loop.h"
#include "slam_options.h"
#include "slam_outputs.h"

using namespace ndtom::slam;
namespace apps = ndtom::apps;

namespace {

enum class Trajectory { Final, Live, Odometry };

const Eigen::Isometry3d& poseOf(const SlamScan& s, Trajectory which) {
  switch (which) {
    case Trajectory::Live:
      return s.live;
    case Trajectory::Odometry:
      return s.odometry;
    case Trajectory::Final:
      break;
  }
  return s.step.pose;
}

// The ATE of the run against --reference (pose i of the file = scan i, or by time stamp).
std::optional<ndtom::TrajectoryError> referenceError(const SlamOptions& o, const SlamResult& r,
                                                     Trajectory which = Trajectory::Final) {
  if (o.reference_file.empty()) return std::nullopt;
  const apps::TrajectoryPoses reference(o.reference_file, ndtom::io::PoseFormat::Auto, 0.02);
  std::vector<Eigen::Vector3d> estimate, truth;
  for (size_t i = 0; i < r.scans.size(); ++i) {
    try {
      truth.push_back(reference.poseFor(i, r.scans[i].step.time).translation());
      estimate.push_back(poseOf(r.scans[i], which).translation());
    } catch (const std::exception&) {  // no reference pose for this scan: left out
    }
  }
  if (estimate.size() < 3)
    throw apps::InputError(o.reference_file + ": fewer than 3 of the scans have a reference pose");
  return ndtom::alignedTrajectoryError(estimate, truth);
}

int run(const SlamOptions& o) {
  const auto start = std::chrono::steady_clock::now();
  const ndtom::mapper::MapperOptions& m = o.map;
  ndtom::mapper::InsertionOptions insertion = ndtom::mapper::resolveInsertionOptions(m.insertion);
  const ndtom::mapper::RunBudget budget = ndtom::mapper::applyRunBudget(insertion, m.insertion, m.input);
  apps::SourceSettings settings = ndtom::mapper::sourceSettingsFor(m, insertion);
  settings.use_poses = false;
  settings.poses_optional = true;
  auto source = apps::openScanSource(settings);
  apps::OutputFiles out(m.prefix);
  if (!m.quiet) std::fprintf(stderr, "ndtom-slam: %s\n", source->description().c_str());
  ndtom::OnlineMapperOptions online = o.online;
  online.map = insertion.toMapOptions();
  online.threads = insertion.scan.threads;
  online.placement.registration.threads = insertion.scan.threads;

  apps::Progress progress(!m.quiet);
  SlamResult result = runOnline(*source, online, o.loops, progress);
  if (result.scans.empty()) throw apps::InputError(m.input + ": no scans");
  if (result.loops) {  // the exact map: every scan again, at its optimized pose
    auto again = apps::openScanSource(settings);
    rebuildAtOptimizedPoses(*again, online, result, progress);
  }
  if (result.points.pointsUsed() == 0)
    throw apps::InputError(m.input + ": no usable point in " + std::to_string(result.scans.size()) +
                           " scans (see --min-range, --max-range)");
  apps::StageTimes times(start);
  times.add("map", result.seconds);
  if (result.loops) times.add("rebuild", result.rebuild_seconds);

  // ndtom-map's outputs, then the trajectory and the summary.
  mrpt_ndtom::CNDTOccupancyMap map(insertion.resolution);
  map.insertionOptions = insertion;
  map.renderOptions = apps::renderOptionsFor(result.map, apps::heightScaleOf(result.map),
                                             m.max_ellipsoids, m.ellipsoid_detail);
  map.setNdtMap(std::move(result.map));
  ndtom::mapper::writeMapOutputs(map, result.sensor_path,
                                 ndtom::mapper::outputSettingsFor(m, insertion), out, times);
  out.writeBytes("trajectory", ".tum", trajectoryTum(result));
  if (result.loops) {
    out.writeBytes("pose graph", ".graph", result.loops->graph_text);
    out.writeBytes("odometry", ".odometry.tum", odometryTum(result));
    if (m.pictures) {
      const apps::HeightScale scale{map.renderOptions.color_min_z, map.renderOptions.color_max_z};
      out.writeBytes(
          "loop closures", ".loops.png",
          apps::pngBytes(loopClosurePicture(map.ndtMap(), scale, result, m.image_width)));
    }
  }
  SlamSummary summary;
  summary.options = &o;
  summary.source_description = source->description();
  summary.result = &result;
  summary.map = &map.ndtMap();
  summary.reference_error = referenceError(o, result);
  if (result.loops) {
    summary.odometry_reference_error = referenceError(o, result, Trajectory::Odometry);
    summary.live_reference_error = referenceError(o, result, Trajectory::Live);
  }
  summary.files = out.files();
  summary.files.push_back({"summary", m.prefix + ".summary.json"});
  summary.peak_rss = apps::peakRssBytes();
  summary.budget = budget;
  summary.total_seconds = apps::secondsSince(start);
  out.writeBytes("summary", ".summary.json", summaryJson(summary));
  out.commit();
  if (!m.quiet) std::fputs(summaryText(summary).c_str(), stdout);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  return apps::runProgram("ndtom-slam", [&] {
    const SlamOptions options = parseSlamOptions(argc, argv);
    if (options.help) {
      std::fputs(helpText().c_str(), stdout);
      return 0;
    }
    return run(options);
  });
}
