#include "scaling.h"

#include <algorithm>
#include <cstdio>
#include <iterator>
#include <stdexcept>

#include "amdahl.h"
#include "ndtom_apps/csv_table.h"

namespace ndtom::bench {

namespace {

std::string format(const char* fmt, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, fmt, v);
  return buf;
}

std::string systemOf(const RunResult& r) {
  return r.label.substr(0, r.label.find('/'));
}

/// Timed calls of a run: scans inserted or registered, over all repeats.
size_t callsOf(const RunResult& r) {
  return r.scan_seconds.size();
}

}  // namespace

const RunResult* oneThreadRun(const std::vector<RunResult>& runs, const RunResult& run) {
  const RunResult* one = findRun(runs, run.dataset, run.resolution, systemOf(run) + "/t1");
  return one && !one->stages.stages.empty() ? one : nullptr;
}

std::optional<double> parallelFractionT1(const std::vector<RunResult>& runs, const RunResult& run) {
  const RunResult* one = oneThreadRun(runs, run);
  if (!one || !(one->totalSeconds() > 0)) return std::nullopt;
  return parallelFraction(one->stages.parallelWallSeconds(), one->totalSeconds());
}

std::optional<double> cpuRatioVsT1(const std::vector<RunResult>& runs, const RunResult& run) {
  const RunResult* one = oneThreadRun(runs, run);
  if (!one || !(one->totalCpuSeconds() > 0)) return std::nullopt;
  return run.totalCpuSeconds() / one->totalCpuSeconds();
}

std::string stagesTable(const std::vector<RunResult>& runs) {
  std::string out =
      "| dataset | system | res (m) | stage | serial ms | parallel wall ms | busy ms (all "
      "threads) | share of time |\n|---|---|---:|---|---:|---:|---:|---:|\n";
  for (const RunResult& r : runs) {
    if (r.stages.stages.empty() || callsOf(r) == 0) continue;
    const double per_call = 1e3 / double(callsOf(r));
    const double total = r.totalSeconds();
    const auto row = [&](const std::string& stage, double serial, double parallel, double busy,
                         double wall) {
      out += "| " + r.dataset + " | " + r.label + " | " + format("%.2f", r.resolution) + " | " +
             stage + " | " + format("%.3f", serial * per_call) + " | " +
             format("%.3f", parallel * per_call) + " | " + format("%.3f", busy * per_call) + " | " +
             (total > 0 ? format("%.1f %%", 100 * wall / total) : "-") + " |\n";
    };
    for (const StageTimes& s : r.stages.stages)
      row(s.name, s.serialSeconds(), s.parallel_wall_seconds, s.busy_seconds, s.wall_seconds);
    // What the stages do not cover (calls, the timer) is serial too.
    const double outside = std::max(0.0, total - r.stages.wallSeconds());
    row("(outside the stages)", outside, 0, 0, outside);
  }
  return out;
}

std::string amdahlTable(const std::vector<RunResult>& runs) {
  std::string out = "| dataset | system | res (m) | p (1 thread) |";
  for (int n : kPredictedThreads) out += " S(" + std::to_string(n) + ") predicted |";
  out += " CPU(16) / 1 thread, workers spinning |";
  out += " measured: threads, speed-up, CPU / 1 thread |\n|---|---|---:|---:|";
  for (size_t i = 0; i <= std::size(kPredictedThreads); ++i) out += "---:|";
  out += "---|\n";
  for (const RunResult& r : runs) {
    if (r.threads != 1) continue;
    const std::optional<double> p = parallelFractionT1(runs, r);
    if (!p) continue;
    out += "| " + r.dataset + " | " + systemOf(r) + " | " + format("%.2f", r.resolution) + " | " +
           format("%.3f", *p) + " |";
    for (int n : kPredictedThreads) out += " " + format("%.2f", amdahlSpeedup(*p, n)) + " |";
    out += " " + format("%.2f", spinningCpuRatio(*p, 16)) + " |";
    std::string measured;
    for (const RunResult& m : runs) {
      if (m.threads <= 1 || m.dataset != r.dataset || m.resolution != r.resolution ||
          systemOf(m) != systemOf(r) || !(m.totalSeconds() > 0))
        continue;
      if (!measured.empty()) measured += "; ";
      measured += std::to_string(m.threads) + ": " +
                  format("%.2fx", r.totalSeconds() / m.totalSeconds()) +
                  (m.paired_speedup ? format(" (side by side %.2fx)", *m.paired_speedup) : "");
      if (const auto cpu = cpuRatioVsT1(runs, m)) measured += format(", CPU %.2f", *cpu);
    }
    out += " " + (measured.empty() ? std::string("-") : measured) + " |\n";
  }
  return out;
}

void writeStagesCsv(const std::string& path, const std::vector<RunResult>& runs) {
  apps::CsvTable table({"dataset", "system", "threads", "resolution_m", "calls", "stage",
                        "stage_calls", "wall_s", "serial_s", "parallel_wall_s", "busy_s",
                        "regions"});
  const auto g = [](double v) { return apps::CsvCell::formatted("%.9g", v); };
  for (const RunResult& r : runs) {
    if (r.stages.stages.empty()) continue;
    for (const StageTimes& s : r.stages.stages)
      table.addRow({r.dataset, r.label, r.threads, g(r.resolution), callsOf(r), s.name,
                    size_t(s.calls), g(s.wall_seconds), g(s.serialSeconds()),
                    g(s.parallel_wall_seconds), g(s.busy_seconds), size_t(s.regions)});
    const double total = r.totalSeconds(), parallel = r.stages.parallelWallSeconds();
    table.addRow({r.dataset, r.label, r.threads, g(r.resolution), callsOf(r), "(all)", callsOf(r),
                  g(total), g(std::max(0.0, total - parallel)), g(parallel),
                  g(r.stages.busySeconds()), ""});
  }
  try {
    table.write(path);
  } catch (const std::exception& e) {
    throw std::runtime_error("--csv (stages): " + std::string(e.what()));
  }
}

}  // namespace ndtom::bench
