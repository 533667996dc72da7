#include "slam_outputs.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <utility>

#include "ndtom_apps/json_writer.h"
#include "ndtom_apps/placement_json.h"
#include "ndtom_apps/statistics.h"

namespace ndtom::slam {
namespace {

// The resolution of the registration level that placed the scan (0: none ran).
double finestLevel(const ndtom::OnlineStep& step) {
  return step.registration.levels.empty() ? 0.0 : step.registration.levels.back().resolution;
}

/// The scans a step's flag marks: how many, and the first.
struct ScanCount {
  size_t first = 0, count = 0;
};

ScanCount countScans(const SlamResult& r, bool ndtom::OnlineStep::*flag) {
  ScanCount out;
  for (const SlamScan& s : r.scans)
    if (s.step.*flag && out.count++ == 0) out.first = s.step.index;
  return out;
}

void writeStep(apps::JsonWriter& j, const SlamScan& s) {
  const ndtom::OnlineStep& st = s.step;
  j.beginObject();
  j.field("index", st.index);
  j.field("name", s.name);
  j.field("time", st.time);
  j.field("points", s.points);
  j.field("outcome", ndtom::toString(st.outcome));
  j.field("found_by", st.found_by);
  j.field("registrations", st.registrations);
  j.field("inserted", st.inserted);
  if (!st.registration.failure.empty()) j.field("failure", st.registration.failure);
  j.field("matched_fraction", st.registration.matched_fraction);
  j.field("judged_fraction", st.registration.judged_fraction);
  j.field("free_fraction", st.registration.free_fraction);
  j.field("weak_directions", st.weak_directions);
  j.field("finest_level_m", finestLevel(st));
  j.field("without_finest", st.without_finest);
  j.field("pose_from_refused_registration", st.pose_from_refused_registration);
  j.field("free_space_overruled", st.free_space_overruled);
  // Registration's correction (both in the live frame, which a loop closure may have moved).
  j.field("correction_m", (s.live.translation() - st.prediction.translation()).norm());
  j.field("sigma_xyz_m",
          std::sqrt(std::max(0.0, st.registration.covariance.topLeftCorner<3, 3>().trace())));
  j.field("target_seconds", st.target_seconds);
  j.field("locate_seconds", st.locate_seconds);
  j.field("insert_seconds", st.insert_seconds);
  j.endObject();
}

std::vector<double> scanSeconds(const SlamResult& r) {
  std::vector<double> v;
  for (const SlamScan& s : r.scans)
    v.push_back(s.step.locate_seconds + s.step.insert_seconds);  // locating includes the target
  return v;
}

void writeLoops(apps::JsonWriter& j, const LoopClosureReport& l, double rebuild_seconds) {
  j.beginObject("loop_closure");
  j.field("keyframes", l.anchors_odometry.size());
  j.field("candidates_checked", l.loops.size());
  j.field("accepted", l.accepted);
  j.field("rejected", l.rejected);
  j.field("optimizations", l.optimizations);
  j.field("restarts", l.restarts);
  j.field("last_optimization_iterations", l.last_optimization.iterations);
  j.field("last_optimization_error_before", l.last_optimization.error_before);
  j.field("last_optimization_error_after", l.last_optimization.error_after);
  j.field("check_seconds", l.check_seconds);
  j.field("optimize_seconds", l.optimize_seconds);
  j.field("window_seconds", l.window_seconds);
  j.field("live_corrections", l.live_corrections);
  j.field("correction_seconds", l.correction_seconds);
  j.field("rebuild_seconds", rebuild_seconds);
  j.beginArray("keyframe_first_scans");
  for (const size_t f : l.keyframe_first_scan) j.field("", f);
  j.endArray();
  j.beginArray("checks");
  for (const LoopRecord& r : l.loops) {
    j.beginObject();
    j.field("older_keyframe", r.older);
    j.field("newer_keyframe", r.newer);
    j.field("older_scan", l.keyframe_first_scan[r.older]);
    j.field("newer_scan", l.keyframe_first_scan[r.newer]);
    j.field("accepted", r.check.accepted);
    j.field("found_by", r.check.found_by);
    if (!r.check.accepted) j.field("rejection", r.check.rejection);
    j.field("disagreement_m", r.check.disagreement_m);
    j.field("disagreement_deg", r.check.disagreement_deg);
    j.field("chi2", r.check.chi2);
    j.field("seconds", r.check.seconds);
    j.endObject();
  }
  j.endArray();
  j.endObject();
}

void writeError(apps::JsonWriter& j, const char* name, const std::string& file,
                const ndtom::TrajectoryError& e) {
  j.beginObject(name);
  j.field("file", file);
  j.field("ate_rmse_m", e.rmse);
  j.field("ate_max_m", e.max);
  j.field("final_error_m", e.final);
  j.field("path_length_m", e.length);
  j.field("final_error_percent", e.length > 0 ? 100 * e.final / e.length : 0.0);
  j.endObject();
}

}  // namespace

std::string odometryTum(const SlamResult& result) {
  std::string text;
  Eigen::Isometry3d unused;
  for (const SlamScan& s : result.scans) text += tumLine(s.step.time, s.odometry, &unused) + "\n";
  return text;
}

std::string trajectoryTum(const SlamResult& result) {
  std::string text;
  for (const SlamScan& s : result.scans) text += s.tum_line + "\n";
  return text;
}

std::string summaryJson(const SlamSummary& s) {
  const SlamResult& r = *s.result;
  const ndtom::OnlineMapperOptions& online = s.options->online;
  const ndtom::PlacementOptions& o = online.placement;
  apps::JsonWriter j;
  j.beginObject();
  j.field("program", "ndtom-slam");
  j.field("input", s.options->map.input);
  j.field("source", s.source_description);
  j.beginObject("options");
  j.field("resolution", s.map->options().resolution);
  j.field("target_radius", online.target_radius);
  j.field("free_space_overrule", online.free_space_overrule);
  j.field("threads", online.threads);
  j.beginObject("placement");
  apps::writePlacementOptions(j, o);
  j.endObject();
  j.endObject();
  j.field("prediction", r.odometry_used ? "odometry" : "constant velocity");
  j.field("scans", r.scans.size());
  j.field("tracked", r.count(ndtom::OnlineOutcome::Tracked));
  j.field("recovered", r.count(ndtom::OnlineOutcome::Recovered));
  j.field("lost", r.count(ndtom::OnlineOutcome::Lost));
  j.field("first", r.count(ndtom::OnlineOutcome::First));
  j.field("map_cells", s.map->numCells());
  j.field("map_gaussians", s.map->numGaussians());
  const std::vector<double> seconds = scanSeconds(r);
  j.field("scan_seconds_median", apps::quantile(seconds, 0.5));
  j.field("placed_without_finest_level", countScans(r, &ndtom::OnlineStep::without_finest).count);
  j.field("lost_at_refused_pose",
          countScans(r, &ndtom::OnlineStep::pose_from_refused_registration).count);
  j.field("free_space_overruled", countScans(r, &ndtom::OnlineStep::free_space_overruled).count);
  j.field("scans_per_second", r.seconds > 0 ? double(r.scans.size()) / r.seconds : 0.0);
  if (s.reference_error) writeError(j, "reference", s.options->reference_file, *s.reference_error);
  if (s.odometry_reference_error)
    writeError(j, "odometry_reference", s.options->reference_file, *s.odometry_reference_error);
  if (s.live_reference_error)
    writeError(j, "live_reference", s.options->reference_file, *s.live_reference_error);
  if (r.loops) writeLoops(j, *r.loops, r.rebuild_seconds);
  j.field("loop_seconds", r.seconds);
  j.field("total_seconds", s.total_seconds);
  j.beginObject("memory");
  mapper::writeRunBudget(j, s.budget);
  j.field("map_bytes", s.map->memoryBytes());
  j.field("peak_rss_bytes", s.peak_rss);
  j.endObject();
  apps::writeFileList(j, s.files);
  j.beginArray("per_scan");
  for (const SlamScan& scan : r.scans) writeStep(j, scan);
  j.endArray();
  j.endObject();
  return j.str();
}

std::string summaryText(const SlamSummary& s) {
  const SlamResult& r = *s.result;
  std::ostringstream t;
  char line[256];
  std::snprintf(line, sizeof(line),
                "ndtom-slam: %zu scans: %zu tracked, %zu recovered, %zu lost (prediction: %s)\n",
                r.scans.size(),
                r.count(ndtom::OnlineOutcome::Tracked) + r.count(ndtom::OnlineOutcome::First),
                r.count(ndtom::OnlineOutcome::Recovered), r.count(ndtom::OnlineOutcome::Lost),
                r.odometry_used ? "odometry" : "constant velocity");
  t << line;
  std::snprintf(line, sizeof(line),
                "  map: %zu cells, %zu Gaussians, %.1f MB; %.2f scans/s, median %.1f ms a scan\n",
                s.map->numCells(), s.map->numGaussians(), double(s.map->memoryBytes()) / 1e6,
                r.seconds > 0 ? double(r.scans.size()) / r.seconds : 0.0,
                1e3 * apps::quantile(scanSeconds(r), 0.5));
  t << line;
  const std::pair<bool ndtom::OnlineStep::*, const char*> flagged[] = {
      {&ndtom::OnlineStep::without_finest,
       "scans placed only without the registration's finest level"},
      {&ndtom::OnlineStep::free_space_overruled,
       "scans placed although only the free-space check refused them: their registration "
       "agreed with the prediction"},
      {&ndtom::OnlineStep::pose_from_refused_registration,
       "lost scans kept the pose only the free-space check refused, not inserted"}};
  for (const auto& [flag, what] : flagged)
    if (const ScanCount c = countScans(r, flag); c.count > 0)
      t << "  " << c.count << " " << what << " (the first: scan " << c.first << ")\n";
  if (s.reference_error) {
    const ndtom::TrajectoryError& e = *s.reference_error;
    std::snprintf(line, sizeof(line),
                  "  against %s: ATE %.3f m RMSE, %.3f m max, final %.3f m (%.2f %% of %.1f m)\n",
                  s.options->reference_file.c_str(), e.rmse, e.max, e.final,
                  e.length > 0 ? 100 * e.final / e.length : 0.0, e.length);
    t << line;
  }
  if (r.loops) {
    const LoopClosureReport& l = *r.loops;
    std::snprintf(line, sizeof(line),
                  "  loop closure: %zu keyframes, %zu loops accepted, %zu candidates rejected; "
                  "checks %.1f s, graph %.2f s, exact map rebuilt in %.1f s\n",
                  l.anchors_odometry.size(), l.accepted, l.rejected, l.check_seconds,
                  l.optimize_seconds, r.rebuild_seconds);
    t << line;
  }
  if (s.odometry_reference_error) {
    const ndtom::TrajectoryError& e = *s.odometry_reference_error;
    std::snprintf(line, sizeof(line),
                  "  odometry before optimization: ATE %.3f m RMSE, %.3f m max, final %.3f m\n",
                  e.rmse, e.max, e.final);
    t << line;
  }
  if (s.live_reference_error) {
    const ndtom::TrajectoryError& e = *s.live_reference_error;
    std::snprintf(line, sizeof(line),
                  "  poses during the run (live map moved at %zu loop closures): ATE %.3f m RMSE, "
                  "%.3f m max, final %.3f m\n",
                  r.loops ? r.loops->live_corrections : size_t(0), e.rmse, e.max, e.final);
    t << line;
  }
  std::snprintf(line, sizeof(line), "  %.1f s in all, peak memory %.0f MB; budget %.0f MB (%s)\n",
                s.total_seconds, double(s.peak_rss) / 1e6, double(s.budget.bytes) / 1e6,
                s.budget.rule.c_str());
  t << line;
  for (const apps::WrittenFile& f : s.files) t << "  " << f.path << "\n";
  return t.str();
}

}  // namespace ndtom::slam
