#include "localize_outputs.h"

#include <algorithm>
#include <cstdio>
#include <iomanip>
#include <sstream>

#include "height_colors.h"
#include "json_writer.h"
#include "png_bytes.h"
#include "run_summary.h"
#include "top_view.h"

namespace ndtom::localizer {
namespace {

std::vector<double> registrationSeconds(const TrackingResult& tracking) {
  std::vector<double> s;
  for (const ScanRecord& r : tracking.scans) s.push_back(r.result.seconds);
  return s;
}

void writePose(mapper::JsonWriter& j, const std::string& key, const Eigen::Isometry3d& pose) {
  const Eigen::Vector3d t = pose.translation();
  const Eigen::Quaterniond q(pose.linear());
  j.beginArray(key);
  for (const double v : {t.x(), t.y(), t.z(), q.x(), q.y(), q.z(), q.w()}) j.field("", v);
  j.endArray();
}

void writeScan(mapper::JsonWriter& j, const ScanRecord& r) {
  j.beginObject();
  j.field("index", r.index);
  j.field("name", r.name);
  j.field("time", r.time);
  j.field("points", r.points);
  j.field("converged", r.result.converged);
  j.field("attempts", r.attempts);
  if (!r.result.converged) j.field("failure", r.result.failure);
  j.field("score", r.result.score);
  j.field("matched_fraction", r.result.matched_fraction);
  j.field("seconds", r.result.seconds);
  j.field("pyramid_rebuilt", r.result.pyramid_rebuilt);
  writePose(j, "pose_xyz_qxyzw", r.pose);
  writePose(j, "prediction_xyz_qxyzw", r.prediction);
  j.beginArray("levels");
  for (const ndtom::LevelReport& l : r.result.levels) {
    j.beginObject();
    j.field("resolution", l.resolution);
    j.field("iterations", l.iterations);
    j.field("evaluations", l.evaluations);
    j.field("scan_items", l.scan_items);
    j.field("score", l.score);
    j.field("matched_fraction", l.matched_fraction);
    j.field("converged", l.converged);
    j.field("seconds", l.seconds);
    j.endObject();
  }
  j.endArray();
  j.endObject();
}

}  // namespace

std::string trajectoryTum(const TrackingResult& tracking) {
  std::ostringstream s;
  s << std::setprecision(9);
  for (const ScanRecord& r : tracking.scans) {
    const Eigen::Vector3d t = r.pose.translation();
    const Eigen::Quaterniond q(r.pose.linear());
    s << std::fixed << std::setprecision(6) << r.time << std::setprecision(9) << ' ' << t.x()
      << ' ' << t.y() << ' ' << t.z() << ' ' << q.x() << ' ' << q.y() << ' ' << q.z() << ' '
      << q.w() << '\n';
  }
  return s.str();
}

std::string summaryJson(const LocalizeSummary& s) {
  const LocalizeOptions& o = *s.options;
  const TrackingResult& t = *s.tracking;
  const std::vector<double> seconds = registrationSeconds(t);
  mapper::JsonWriter j;
  j.beginObject();
  j.field("map", o.map_path);
  j.field("map_resolution", s.map_resolution);
  j.field("map_cells", s.map_cells);
  j.field("map_gaussians", s.map_gaussians);
  j.field("map_load_seconds", s.map_load_seconds);
  j.field("input", o.input);
  j.field("source", s.source_description);
  j.beginObject("registration");
  j.field("method", ndtom::toString(o.registration.method));
  j.beginArray("level_factors");
  for (const int f : o.registration.level_factors) j.field("", f);
  j.endArray();
  j.field("outlier_ratio", o.registration.outlier_ratio);
  j.field("max_iterations", o.registration.max_iterations);
  j.field("min_range", o.registration.min_range);
  j.field("max_range", o.registration.max_range);
  j.field("max_points", o.registration.max_points);
  j.field("min_matched_fraction", o.registration.min_matched_fraction);
  j.field("planar", o.registration.planar);
  j.field("threads", o.registration.threads);
  j.endObject();
  j.field("scans", t.scans.size());
  j.field("converged", t.converged());
  j.field("failed", t.scans.size() - t.converged());
  j.field("registration_seconds_median", mapper::percentile(seconds, 0.5));
  j.field("registration_seconds_p95", mapper::percentile(seconds, 0.95));
  j.field("scans_per_second", t.seconds > 0 ? double(t.scans.size()) / t.seconds : 0.0);
  j.field("tracking_seconds", t.seconds);
  j.field("total_seconds", s.total_seconds);
  j.field("peak_rss_bytes", s.peak_rss);
  j.beginArray("files");
  for (const auto& f : s.files) {
    j.beginObject();
    j.field("role", f.role);
    j.field("path", f.path);
    j.endObject();
  }
  j.endArray();
  j.beginArray("per_scan");
  for (const ScanRecord& r : t.scans) writeScan(j, r);
  j.endArray();
  j.endObject();
  return j.str();
}

std::string summaryText(const LocalizeSummary& s) {
  const TrackingResult& t = *s.tracking;
  const std::vector<double> seconds = registrationSeconds(t);
  std::ostringstream out;
  out << std::fixed << std::setprecision(1);
  out << "localized " << t.converged() << " of " << t.scans.size() << " scans ("
      << t.scans.size() - t.converged() << " failed) in " << s.map_resolution << " m cells";
  out.precision(2);
  out << " (" << s.map_gaussians << " Gaussians)\n"
      << "registration: median " << 1e3 * mapper::percentile(seconds, 0.5) << " ms, p95 "
      << 1e3 * mapper::percentile(seconds, 0.95) << " ms; "
      << (t.seconds > 0 ? double(t.scans.size()) / t.seconds : 0.0) << " scans/s with reading; "
      << "total " << s.total_seconds << " s, peak memory " << double(s.peak_rss) / (1 << 20)
      << " MiB\n";
  for (const auto& f : s.files) out << "  " << f.role << ": " << f.path << "\n";
  return out.str();
}

void writeTrajectoryOutputs(const ndtom::NdtMap& map, const TrackingResult& tracking,
                            const LocalizeOptions& options, mapper::OutputFiles& out) {
  out.writeBytes("trajectory", ".tum", trajectoryTum(tracking));
  if (!options.pictures) return;
  std::vector<Eigen::Vector3d> path;
  for (const ScanRecord& r : tracking.scans) path.push_back(r.pose.translation());
  out.writeBytes("top_view", ".top.png",
                 mapper::pngBytes(mapper::renderTopView(map, mapper::heightScaleOf(map), path,
                                                        options.image_width)));
}

}  // namespace ndtom::localizer
