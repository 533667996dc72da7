#include "localize_outputs.h"

#include <algorithm>
#include <cstdio>
#include <iomanip>
#include <sstream>

#include "localize_accuracy.h"
#include "ndtom_apps/csv_table.h"
#include "ndtom_apps/height_colors.h"
#include "ndtom_apps/json_writer.h"
#include "ndtom_apps/placement_json.h"
#include "ndtom_apps/png_bytes.h"
#include "ndtom_apps/statistics.h"
#include "ndtom_apps/top_view.h"

namespace ndtom::localizer {
namespace {

std::vector<double> scanSeconds(const TrackingResult& tracking) {
  std::vector<double> s;
  for (const ScanRecord& r : tracking.scans) s.push_back(r.seconds);
  return s;
}

// Green up to 5 cm, then through yellow (10 cm) to red at 15 cm and beyond (BGR).
cv::Scalar errorColour(double metres) {
  const double f = std::clamp((metres - 0.05) / 0.10, 0.0, 1.0);
  return f < 0.5 ? cv::Scalar(0, 170 + 170 * f, 510 * f) : cv::Scalar(0, 255 * (2 - 2 * f), 255);
}

void writePose(apps::JsonWriter& j, const std::string& key, const Eigen::Isometry3d& pose) {
  const Eigen::Vector3d t = pose.translation();
  const Eigen::Quaterniond q(pose.linear());
  j.beginArray(key);
  for (const double v : {t.x(), t.y(), t.z(), q.x(), q.y(), q.z(), q.w()}) j.field("", v);
  j.endArray();
}

void writeScan(apps::JsonWriter& j, const ScanRecord& r) {
  j.beginObject();
  j.field("index", r.index);
  j.field("name", r.name);
  j.field("time", r.time);
  j.field("points", r.points);
  j.field("outcome", toString(r.outcome));
  j.field("found_by", r.found_by);
  j.field("registrations", r.registrations);
  j.field("weak_directions", r.weak_directions);
  if (r.outcome == Outcome::Lost) j.field("failure", r.result.failure);
  if (const auto e = errorOf(r)) {
    j.field("error_m", e->translation);
    j.field("error_deg", e->rotation);
  }
  j.field("score", r.result.score);
  j.field("matched_fraction", r.result.matched_fraction);
  j.field("judged_fraction", r.result.judged_fraction);
  j.field("placed_in", placedIn(r));
  j.field("in_prior", r.in_prior);
  j.field("in_live", r.in_live);
  j.field("free_fraction", r.result.free_fraction);
  j.field("seconds", r.seconds);
  if (r.pose) writePose(j, "pose_xyz_qxyzw", *r.pose);
  if (r.prediction) writePose(j, "prediction_xyz_qxyzw", *r.prediction);
  if (r.reference) writePose(j, "reference_xyz_qxyzw", *r.reference);
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
  for (const ScanRecord& r : tracking.scans) {
    if (!r.pose || r.outcome == Outcome::Lost) continue;
    const Eigen::Vector3d t = r.pose->translation();
    const Eigen::Quaterniond q(r.pose->linear());
    s << std::fixed << std::setprecision(6) << r.time << std::setprecision(9) << ' ' << t.x() << ' '
      << t.y() << ' ' << t.z() << ' ' << q.x() << ' ' << q.y() << ' ' << q.z() << ' ' << q.w()
      << '\n';
  }
  return s.str();
}

std::string scansCsv(const TrackingResult& tracking) {
  apps::CsvTable table({"index",
                        "time",
                        "outcome",
                        "found_by",
                        "registrations",
                        "x",
                        "y",
                        "z",
                        "qx",
                        "qy",
                        "qz",
                        "qw",
                        "error_m",
                        "error_deg",
                        "matched_fraction",
                        "judged_fraction",
                        "free_fraction",
                        "placed_in",
                        "in_prior",
                        "in_live",
                        "seconds",
                        "map_bytes",
                        "rss_bytes"});
  const auto g9 = [](double v) { return apps::CsvCell::formatted("%.9g", v); };
  for (const ScanRecord& r : tracking.scans) {
    std::vector<apps::CsvCell> row = {r.index, apps::CsvCell::formatted("%.6f", r.time),
                                      toString(r.outcome), r.found_by, r.registrations};
    if (r.pose && r.outcome != Outcome::Lost) {
      const Eigen::Vector3d t = r.pose->translation();
      const Eigen::Quaterniond q(r.pose->linear());
      for (const double v : {t.x(), t.y(), t.z(), q.x(), q.y(), q.z(), q.w()}) row.push_back(g9(v));
    } else {
      row.insert(row.end(), 7, apps::CsvCell(""));
    }
    const auto e = errorOf(r);
    row.insert(row.end(), {e ? std::to_string(e->translation) : "",
                           e ? std::to_string(e->rotation) : "", g9(r.result.matched_fraction),
                           g9(r.result.judged_fraction), g9(r.result.free_fraction), placedIn(r),
                           g9(r.in_prior), g9(r.in_live), g9(r.seconds), r.map_bytes, r.rss_bytes});
    table.addRow(row);
  }
  return table.text();
}

std::string summaryJson(const LocalizeSummary& s) {
  const LocalizeOptions& o = *s.options;
  const TrackingResult& t = *s.tracking;
  const std::vector<double> seconds = scanSeconds(t);
  apps::JsonWriter j;
  j.beginObject();
  j.field("map", o.map_path);
  j.field("map_resolution", s.map_resolution);
  j.field("map_cells", s.map_cells);
  j.field("map_gaussians", s.map_gaussians);
  j.field("map_load_seconds", s.map_load_seconds);
  if (s.region) {
    j.beginObject("region");  // the tiles resident around the robot
    j.field("radius_m", s.region->radius);
    j.field("tiles_in_file", s.region->tiles);
    j.field("loads", s.region->loads);
    j.field("drops", s.region->drops);
    j.field("max_resident_tiles", s.region->max_resident_tiles);
    j.field("max_resident_map_bytes", s.region->max_resident_bytes);
    j.endObject();
  }
  j.field("input", o.input);
  j.field("source", s.source_description);
  j.beginObject("registration");
  apps::writePlacementOptions(j, o.tracking.placement);
  j.endObject();
  j.field("initial_given", o.tracking.initial.has_value());
  j.field("relocalize_after", o.tracking.relocalize_after);
  j.field("global_every_scan", o.tracking.global_every_scan);
  j.field("prediction", t.odometry_used ? "odometry" : "constant velocity");
  j.field("scans", t.scans.size());
  j.field("localized", t.localized());
  j.field("tracked", t.count(Outcome::Tracked));
  j.field("recovered", t.count(Outcome::Recovered));
  j.field("relocalized", t.count(Outcome::Relocalized));
  j.field("lost", t.count(Outcome::Lost));
  j.field("global_searches", t.global_searches);
  j.field("live_map", o.tracking.live.enabled);
  size_t by_live = 0, by_both = 0;
  for (const ScanRecord& r : t.scans) {
    by_live += placedIn(r) == std::string("live");
    by_both += placedIn(r) == std::string("prior+live");
  }
  j.field("placed_in_live_map_only", by_live);
  j.field("placed_in_both_maps", by_both);
  if (const auto a = accuracyOf(t)) {
    j.beginObject("accuracy");
    j.field("scans", a->scans);
    j.field("ate_rmse_m", a->rmse);
    j.field("ate_max_m", a->max);
    j.field("rotation_rmse_deg", a->rotation_rmse);
    j.field("rotation_max_deg", a->rotation_max);
    j.endObject();
  }
  j.field("scan_seconds_median", apps::percentile(seconds, 0.5));
  j.field("scan_seconds_p95", apps::percentile(seconds, 0.95));
  j.field("scans_per_second", t.seconds > 0 ? double(t.scans.size()) / t.seconds : 0.0);
  j.field("tracking_seconds", t.seconds);
  j.field("total_seconds", s.total_seconds);
  j.field("peak_rss_bytes", s.peak_rss);
  apps::writeFileList(j, s.files);
  j.beginArray("per_scan");
  for (const ScanRecord& r : t.scans) writeScan(j, r);
  j.endArray();
  j.endObject();
  return j.str();
}

std::string summaryText(const LocalizeSummary& s) {
  const TrackingResult& t = *s.tracking;
  const std::vector<double> seconds = scanSeconds(t);
  std::ostringstream out;
  out << std::fixed << std::setprecision(1);
  out << "localized " << t.localized() << " of " << t.scans.size() << " scans ("
      << t.count(Outcome::Lost) << " lost) in " << s.map_resolution << " m cells ("
      << s.map_gaussians << " Gaussians): " << t.count(Outcome::Tracked) << " tracked, "
      << t.count(Outcome::Recovered) << " recovered, " << t.count(Outcome::Relocalized)
      << " found by global search\n";
  size_t by_live = 0, by_both = 0;
  for (const ScanRecord& r : t.scans) {
    by_live += placedIn(r) == std::string("live");
    by_both += placedIn(r) == std::string("prior+live");
  }
  if (by_live + by_both > 0)
    out << "placed with the live map of the localized scans: " << by_live + by_both << " scans ("
        << by_live << " by it alone, where the prior map does not reach)\n";
  if (const auto a = accuracyOf(t)) {
    out << std::setprecision(3) << "error to the reference (" << a->scans << " scans): RMSE "
        << a->rmse << " m, max " << a->max << " m; rotation RMSE " << a->rotation_rmse
        << " deg, max " << a->rotation_max << " deg\n";
  }
  out << std::setprecision(2) << "per scan: median " << 1e3 * apps::percentile(seconds, 0.5)
      << " ms, p95 " << 1e3 * apps::percentile(seconds, 0.95) << " ms; "
      << (t.seconds > 0 ? double(t.scans.size()) / t.seconds : 0.0) << " scans/s with reading; "
      << "total " << s.total_seconds << " s, peak memory " << double(s.peak_rss) / (1 << 20)
      << " MiB\n";
  for (const auto& f : s.files) out << "  " << f.role << ": " << f.path << "\n";
  return out.str();
}

void writeTrajectoryOutputs(const ndtom::NdtMap& map, const TrackingResult& tracking,
                            const LocalizeOptions& options, apps::OutputFiles& out) {
  out.writeBytes("trajectory", ".tum", trajectoryTum(tracking));
  out.writeBytes("scans", ".scans.csv", scansCsv(tracking));
  if (!options.pictures) return;
  apps::ColouredPath path;
  const bool errors = accuracyOf(tracking).has_value();
  for (const ScanRecord& r : tracking.scans) {
    if (r.reference) path.reference.push_back(r.reference->translation());
    if (!r.pose) continue;
    path.points.push_back(r.pose->translation());
    const auto e = errorOf(r);
    path.colours.push_back(r.outcome == Outcome::Lost ? cv::Scalar(255, 0, 255)
                           : e                        ? errorColour(e->translation)
                                                      : cv::Scalar(0, 0, 0));
  }
  path.legend = errors ? "path coloured by error to the reference (thin grey): green <= 5 cm, "
                         "yellow 10 cm, red >= 15 cm, magenta lost; start o"
                       : "black: localized path from o, magenta: lost scans";
  out.writeBytes("top_view", ".top.png",
                 apps::pngBytes(apps::renderTopView(map, apps::heightScaleOf(map), path,
                                                    options.image_width)));
}

}  // namespace ndtom::localizer
