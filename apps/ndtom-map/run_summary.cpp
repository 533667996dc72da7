#include "run_summary.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "ndtom_apps/json_writer.h"
#include "ndtom_apps/statistics.h"

namespace ndtom::mapper {
namespace {

double median(const std::vector<double>& v) {
  return apps::percentile(v, 0.5);
}

void writePoints(apps::JsonWriter& j, const ndtom::InsertionReport& p,
                 const apps::SourceSkips& skips) {
  j.beginObject("points");
  j.field("in", p.points_in);
  j.field("used", p.pointsUsed());
  j.field("hits", p.hits);
  j.field("truncated_at_max_range", p.truncated);
  j.field("rejected", p.rejected());
  j.beginObject("rejected_by_reason");
  j.field("non_finite", p.rejected_non_finite);
  j.field("too_close", p.rejected_too_close);
  j.field("out_of_grid", p.rejected_out_of_grid);
  j.field("too_far", p.rejected_too_far);
  j.endObject();
  j.field("decimated", skips.points_decimated);
  j.endObject();
  j.beginObject("skipped");
  j.field("unsupported_observations", skips.unsupported_observations);
  j.field("scans_without_pose", skips.scans_without_pose);
  j.field("frames_without_pose", skips.frames_without_pose);
  j.endObject();
}

// What the map holds after a pass: the same fields in "map" and in each of "passes".
void writeMapCounts(apps::JsonWriter& j, const PassResult& p) {
  j.field("cells", p.cells);
  j.field("gaussians", p.gaussians);
  j.field("occupied_cells", p.occupied);
  j.field("free_cells", p.free);
  j.field("map_bytes", p.map_bytes);
}

void writePasses(apps::JsonWriter& j, const std::vector<PassResult>& passes) {
  j.beginArray("passes");
  for (size_t i = 0; i < passes.size(); ++i) {
    const PassResult& p = passes[i];
    j.beginObject();
    j.field("pass", i + 1);
    j.field("scans", p.scans);
    writeMapCounts(j, p);
    j.field("rss_bytes", p.rss_bytes);
    j.field("seconds", p.seconds);
    j.endObject();
  }
  j.endArray();
  const PassDrift drift = passDrift(passes);
  j.field("cells_drift_percent", drift.cells_percent);
  j.field("map_bytes_drift_percent", drift.map_bytes_percent);
}

// What a file is, for a newcomer reading the list.
std::string describe(const std::string& role) {
  if (role == "map") return "the map (project format, ndtom::loadMap)";
  if (role == "mrpt_map") return "the map as an MRPT CNDTOccupancyMap object";
  if (role == "scene") return "3D scene for MRPT's SceneViewer3D";
  if (role == "top_view") return "picture: the map from above";
  if (role == "view_3d") return "picture: the map in 3D";
  if (role == "coarse_map") return "the map, coarser (project format)";
  if (role == "octomap") return "the map as an OctoMap (octovis, OctoMap's tools)";
  if (role == "tiled_map") return "the map in tiles, loadable by region (ndtom-localize)";
  if (role == "summary") return "these figures, as JSON";
  return role;
}

void writeMapAndCosts(apps::JsonWriter& j, const RunSummary& s) {
  const MappingResult& m = *s.mapping;
  const PassResult& last = m.passes.back();
  j.beginObject("map");
  writeMapCounts(j, last);
  j.endObject();
  if (s.coarse) {
    j.beginObject("coarse_map");
    j.field("factor", s.coarse->factor);
    j.field("resolution_m", s.coarse->resolution);
    j.field("cells", s.coarse->cells);
    j.field("gaussians", s.coarse->gaussians);
    j.endObject();
  }
  j.beginObject("time");
  j.field("insert_ms_median", 1e3 * median(m.insert_seconds));
  j.field("insert_ms_p95", 1e3 * apps::percentile(m.insert_seconds, 0.95));
  j.field("total_s", s.total_seconds);
  if (s.stages) {
    j.beginObject("stages_s");
    for (const auto& stage : s.stages->stages()) j.field(stage.name, stage.seconds);
    j.endObject();
    j.beginObject("stage_end_s");  // from the start; the scene is written beside the others
    for (const auto& stage : s.stages->stages()) j.field(stage.name, stage.end_s);
    j.endObject();
  }
  j.endObject();
  j.beginObject("memory");
  writeRunBudget(j, s.budget);
  j.field("map_bytes", last.map_bytes);
  j.field("peak_rss_after_mapping_bytes", s.peak_rss_after_mapping);
  j.field("peak_rss_bytes", s.peak_rss);
  if (s.out_of_core) {
    const OutOfCoreInfo& o = *s.out_of_core;
    j.beginObject("out_of_core");
    j.field("resident_budget_bytes", o.resident_budget);
    j.field("tile_blocks", o.tile_blocks);
    j.field("peak_resident_bytes", o.stats.peak_resident_bytes);
    j.field("spills", o.stats.spills);
    j.field("loads", o.stats.loads);
    j.field("spilled_bytes", o.stats.spilled_bytes);
    j.endObject();
  }
  if (s.stages) {
    j.beginObject("peak_rss_after_stage_bytes");
    for (const auto& stage : s.stages->stages()) j.field(stage.name, stage.peak_rss_bytes);
    j.endObject();
  }
  j.endObject();
}

double megabytes(size_t bytes) {
  return double(bytes) / 1e6;
}

}  // namespace

PassDrift passDrift(const std::vector<PassResult>& passes) {
  PassDrift d;
  if (passes.empty()) return d;
  const PassResult& first = passes.front();
  for (const PassResult& p : passes) {
    if (first.cells > 0)
      d.cells_percent = std::max(
          d.cells_percent, 100.0 * std::abs(double(p.cells) - double(first.cells)) / first.cells);
    if (first.map_bytes > 0)
      d.map_bytes_percent =
          std::max(d.map_bytes_percent, 100.0 * std::abs(double(p.map_bytes) - first.map_bytes) /
                                            double(first.map_bytes));
  }
  return d;
}

std::string summaryJson(const RunSummary& s) {
  const MappingResult& m = *s.mapping;
  const PassResult& last = m.passes.back();
  apps::JsonWriter j;
  j.beginObject();
  j.field("input", s.input);
  j.field("format", s.format);
  j.field("source", m.source_description);
  j.field("resolution_m", s.map_options.resolution);
  j.field("ray_mode", ndtom::toString(s.map_options.scan.ray_mode));
  j.field("occupancy_enabled", s.map_options.occupancy.enabled);
  j.field("threads", s.threads);
  j.field("scans", last.scans);
  j.field("scans_inserted", m.insert_seconds.size());
  writePoints(j, m.points, m.skips);
  writeMapAndCosts(j, s);
  writePasses(j, m.passes);
  apps::writeFileList(j, s.files);
  j.endObject();
  return j.str();
}

std::string summaryText(const RunSummary& s) {
  const MappingResult& m = *s.mapping;
  const PassResult& last = m.passes.back();
  const ndtom::InsertionReport& p = m.points;
  char buffer[1024];
  std::string text;
  std::snprintf(buffer, sizeof buffer,
                "  map     %g m cells: %zu cells, %zu Gaussians, %zu occupied, %zu free; %.1f MB\n"
                "  points  %zu read, %zu used, %zu rejected (non-finite %zu, too close %zu, "
                "out of grid %zu, too far %zu)\n"
                "  time    %.1f ms per scan (median), %.1f ms (p95), %.1f s in all; "
                "peak RSS %.0f MB\n",
                s.map_options.resolution, last.cells, last.gaussians, last.occupied, last.free,
                megabytes(last.map_bytes), p.points_in, p.pointsUsed(), p.rejected(),
                p.rejected_non_finite, p.rejected_too_close, p.rejected_out_of_grid,
                p.rejected_too_far, 1e3 * median(m.insert_seconds),
                1e3 * apps::percentile(m.insert_seconds, 0.95), s.total_seconds,
                megabytes(s.peak_rss));
  text += buffer;
  std::snprintf(buffer, sizeof buffer, "  budget  %.0f MB (%s)\n", megabytes(s.budget.bytes),
                s.budget.rule.c_str());
  text += buffer;
  if (s.stages && !s.stages->stages().empty()) {
    text += "  stages ";
    for (const auto& stage : s.stages->stages()) {
      std::snprintf(buffer, sizeof buffer, " %s %.2f s,", stage.name.c_str(), stage.seconds);
      text += buffer;
    }
    text.back() = '\n';
  }
  if (s.out_of_core) {
    const OutOfCoreInfo& o = *s.out_of_core;
    std::snprintf(buffer, sizeof buffer,
                  "  out of core  budget %.1f MB, peak resident %.1f MB; %zu tiles spilled "
                  "(%.1f MB), %zu read back\n",
                  megabytes(o.resident_budget), megabytes(o.stats.peak_resident_bytes),
                  o.stats.spills, megabytes(o.stats.spilled_bytes), o.stats.loads);
    text += buffer;
  }
  if (m.passes.size() > 1) {
    const PassDrift d = passDrift(m.passes);
    for (size_t i = 0; i < m.passes.size(); ++i) {
      std::snprintf(buffer, sizeof buffer, "  pass %-3zu %zu cells, %zu Gaussians, %.1f MB\n",
                    i + 1, m.passes[i].cells, m.passes[i].gaussians,
                    megabytes(m.passes[i].map_bytes));
      text += buffer;
    }
    std::snprintf(buffer, sizeof buffer,
                  "  passes  cells within %.2f %%, map memory within %.2f %% of the first pass\n",
                  d.cells_percent, d.map_bytes_percent);
    text += buffer;
  }
  text += "Wrote:\n";
  size_t width = 0;
  for (const apps::WrittenFile& f : s.files) width = std::max(width, f.path.size());
  for (const apps::WrittenFile& f : s.files)
    text += "  " + f.path + std::string(width + 2 - f.path.size(), ' ') + describe(f.role) + "\n";
  return text;
}

}  // namespace ndtom::mapper
