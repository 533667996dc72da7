#include "report.h"

#include <algorithm>
#include <cstdio>
#include <iterator>
#include <stdexcept>

#include "amdahl.h"
#include "ndtom_apps/csv_table.h"
#include "scaling.h"

namespace ndtom::bench {

namespace {

constexpr const char* kOctomap = "octomap";
constexpr const char* kGrid3d = "mrpt-grid3d";

std::string format(const char* fmt, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, fmt, v);
  return buf;
}

/// "wall (CPU)" ratios for single-thread runs, wall only for threaded ones.
std::string ratioText(const std::vector<RunResult>& runs, const RunResult& r,
                      const std::string& other) {
  const auto wall = timeRatio(runs, r, other);
  if (!wall) return "-";
  const auto cpu = timeRatio(runs, r, other, true);
  if (r.threads > 1 || !cpu) return format("%.3f", *wall);
  return format("%.3f", *wall) + format(" (%.3f)", *cpu);
}

std::string optionalText(const std::optional<double>& v) {
  return v ? std::to_string(*v) : "";
}

std::string mismatchText(const std::optional<MapComparison>& c) {
  return c ? format("%.4f", c->occupancy_mismatch) : "";
}

}  // namespace

std::optional<double> timeRatio(const std::vector<RunResult>& runs, const RunResult& run,
                                const std::string& other_label, bool cpu_time) {
  const RunResult* other = findRun(runs, run.dataset, run.resolution, other_label);
  if (!other) return std::nullopt;
  const double mine = cpu_time ? run.medianCpuSeconds() : run.medianSeconds();
  const double theirs = cpu_time ? other->medianCpuSeconds() : other->medianSeconds();
  if (!(theirs > 0)) return std::nullopt;
  return mine / theirs;
}

std::optional<double> oneThreadSpeedup(const std::vector<RunResult>& runs, const RunResult& run) {
  if (run.threads <= 1) return std::nullopt;
  const std::string one = run.label.substr(0, run.label.find('/')) + "/t1";
  const RunResult* other = findRun(runs, run.dataset, run.resolution, one);
  if (!other || !(run.totalSeconds() > 0)) return std::nullopt;
  return other->totalSeconds() / run.totalSeconds();
}

std::string resultsTable(const std::vector<RunResult>& runs) {
  std::string out =
      "| dataset | system | res (m) | median ms/scan | p95 ms/scan | median CPU ms | Mpoints/s | "
      "Mvisits/s | "
      "CPU/wall | peak RSS Δ (MB) | map (MB) | B/cell | cells | t/t_octomap wall (CPU) | "
      "t/t_grid3d wall (CPU) |\n"
      "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
  for (const RunResult& r : runs) {
    out += "| " + r.dataset + " | " + r.label + " | " + format("%.2f", r.resolution) + " | " +
           format("%.2f", r.medianSeconds() * 1e3) + " | " + format("%.2f", r.p95Seconds() * 1e3) +
           " | " + format("%.2f", r.medianCpuSeconds() * 1e3) + " | " +
           format("%.2f", r.pointsPerSecond() * 1e-6) + " | " +
           format("%.1f", r.visitsPerSecond() * 1e-6) + " | " + format("%.2f", r.cpuPerWall()) +
           " | " + (r.peak_rss_valid ? format("%.1f", double(r.peak_rss_delta) / 1e6) : "n/a") +
           " | " + format("%.1f", double(r.map.memory_bytes) / 1e6) + " | " +
           format("%.1f", r.bytesPerCell()) + " | " + std::to_string(r.map.cells) + " | " +
           ratioText(runs, r, kOctomap) + " | " + ratioText(runs, r, kGrid3d) + " |\n";
  }
  return out;
}

std::string comparisonTable(const std::vector<RunResult>& runs) {
  std::string out =
      "| dataset | system | res (m) | identical to /t1 | speed-up vs /t1: separate runs, side by "
      "side | Gaussians (exact → this) | occupancy mismatch vs exact | similarity vs exact |\n"
      "|---|---|---:|---|---|---|---:|---:|\n";
  for (const RunResult& r : runs) {
    if (!r.vs_exact && !r.vs_one_thread) continue;
    const std::string identical =
        r.vs_one_thread ? (r.vs_one_thread->identical ? "yes" : "NO") : "-";
    std::string gaussians = "-", mismatch = "-", similarity = "-";
    if (r.vs_exact) {
      gaussians = std::to_string(r.vs_exact->gaussians_reference) + " → " +
                  std::to_string(r.vs_exact->gaussians_test);
      mismatch = format("%.2f %%", 100 * r.vs_exact->occupancy_mismatch);
      similarity =
          r.vs_exact->similarity ? format("%.4f", *r.vs_exact->similarity) : "n/a (not in core)";
    }
    std::string speedup = "-";
    if (const auto separate = oneThreadSpeedup(runs, r))
      speedup = format("%.2fx", *separate) +
                (r.paired_speedup ? format(", %.2fx", *r.paired_speedup) : std::string());
    out += "| " + r.dataset + " | " + r.label + " | " + format("%.2f", r.resolution) + " | " +
           identical + " | " + speedup + " | " + gaussians + " | " + mismatch + " | " + similarity +
           " |\n";
  }
  return out;
}

void writeCsv(const std::string& path, const std::vector<RunResult>& runs) {
  apps::CsvTable table({"dataset",
                        "system",
                        "threads",
                        "resolution_m",
                        "scans",
                        "repeats",
                        "median_ms",
                        "p95_ms",
                        "points_per_s",
                        "voxel_visits_per_s",
                        "points",
                        "voxel_visits",
                        "peak_rss_delta_bytes",
                        "memory_bytes",
                        "cells",
                        "bytes_per_cell",
                        "ratio_octomap",
                        "ratio_grid3d",
                        "repeat_median_min_ms",
                        "repeat_median_max_ms",
                        "identical_to_t1",
                        "gaussians",
                        "occupancy_mismatch_vs_exact",
                        "similarity_vs_exact",
                        "cpu_per_wall",
                        "median_cpu_ms",
                        "ratio_octomap_cpu",
                        "ratio_grid3d_cpu",
                        "speedup_vs_t1",
                        "speedup_vs_t1_side_by_side",
                        "parallel_fraction_t1",
                        "predicted_s2",
                        "predicted_s4",
                        "predicted_s8",
                        "predicted_s16",
                        "predicted_cpu16_spinning",
                        "cpu_ratio_vs_t1"});
  const auto g = [](double v) { return apps::CsvCell::formatted("%g", v); };
  for (const RunResult& r : runs) {
    const auto [lo, hi] =
        std::minmax_element(r.repeat_median_seconds.begin(), r.repeat_median_seconds.end());
    const std::string identical = r.vs_one_thread ? (r.vs_one_thread->identical ? "1" : "0") : "";
    const std::optional<double> p = parallelFractionT1(runs, r);
    const auto predicted = [&](int n) {
      return p ? apps::CsvCell(g(amdahlSpeedup(*p, n))) : apps::CsvCell("");
    };
    static_assert(std::size(kPredictedThreads) == 4, "a column each");
    table.addRow({r.dataset,
                  r.label,
                  r.threads,
                  g(r.resolution),
                  r.scan_seconds.size() / size_t(std::max(1, r.repeats)),
                  r.repeats,
                  g(r.medianSeconds() * 1e3),
                  g(r.p95Seconds() * 1e3),
                  g(r.pointsPerSecond()),
                  g(r.visitsPerSecond()),
                  size_t(r.points),
                  size_t(r.voxel_visits),
                  r.peak_rss_valid ? std::to_string(r.peak_rss_delta) : "",
                  r.map.memory_bytes,
                  r.map.cells,
                  g(r.bytesPerCell()),
                  optionalText(timeRatio(runs, r, kOctomap)),
                  optionalText(timeRatio(runs, r, kGrid3d)),
                  g(*lo * 1e3),
                  g(*hi * 1e3),
                  identical,
                  r.vs_exact ? std::to_string(r.vs_exact->gaussians_test) : "",
                  mismatchText(r.vs_exact),
                  r.vs_exact ? optionalText(r.vs_exact->similarity) : "",
                  g(r.cpuPerWall()),
                  g(r.medianCpuSeconds() * 1e3),
                  optionalText(timeRatio(runs, r, kOctomap, true)),
                  optionalText(timeRatio(runs, r, kGrid3d, true)),
                  optionalText(oneThreadSpeedup(runs, r)),
                  optionalText(r.paired_speedup),
                  p ? g(*p) : apps::CsvCell(""),
                  predicted(2),
                  predicted(4),
                  predicted(8),
                  predicted(16),
                  p ? g(spinningCpuRatio(*p, 16)) : apps::CsvCell(""),
                  optionalText(cpuRatioVsT1(runs, r))});
  }
  try {
    table.write(path);
  } catch (const std::exception& e) {
    throw std::runtime_error("--csv: " + std::string(e.what()));
  }
}

}  // namespace ndtom::bench
