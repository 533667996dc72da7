#include "results_csv.h"

#include <Eigen/Geometry>
#include <algorithm>

#include "ndtom_apps/csv_table.h"

namespace ndtom::regbench {

namespace {

using apps::CsvCell;

/// The values of one pyramid figure, ';'-separated in one field.
template <typename Field>
std::string joined(const std::vector<PyramidLevelTime>& levels, Field field) {
  std::string out;
  for (const PyramidLevelTime& p : levels) out += (out.empty() ? "" : ";") + CsvCell(field(p)).text;
  return out;
}

CsvCell optionalCount(const std::optional<VerdictCounts>& v, int VerdictCounts::*count) {
  return v ? CsvCell((*v).*count) : CsvCell("");
}

CsvCell optionalRate(const std::optional<VerdictCounts>& v, int VerdictCounts::*count, int trials) {
  return v && trials > 0 ? CsvCell(double((*v).*count) / trials) : CsvCell("");
}

CsvCell optionalNumber(const std::optional<double>& v) {
  return v ? CsvCell(*v) : CsvCell("");
}

const SystemRun& runOf(const std::vector<SystemRun>& runs, const std::string& label) {
  return *std::find_if(runs.begin(), runs.end(),
                       [&](const SystemRun& r) { return r.label == label; });
}

}  // namespace

void writeLevelsCsv(const std::string& path, const std::string& dataset,
                    const std::vector<SystemRun>& runs,
                    const std::vector<LevelSummary>& summaries) {
  apps::CsvTable table({"dataset",
                        "system",
                        "threads",
                        "translation_m",
                        "rotation_deg",
                        "trials",
                        "successes",
                        "success_rate",
                        "median_error_m",
                        "median_error_deg",
                        "median_ms",
                        "p95_ms",
                        "median_cpu_ms",
                        "converged",
                        "wrong_converged",
                        "wrong_converged_rate",
                        "false_failures",
                        "false_failure_rate",
                        "setup_s",
                        "first_call_ms",
                        "level_resolutions_m",
                        "level_mean_ms",
                        "level_mean_iterations"});
  for (const LevelSummary& s : summaries) {
    const SystemRun& run = runOf(runs, s.label);
    const auto& v = s.verdicts;
    table.addRow({dataset,
                  s.label,
                  s.threads,
                  s.level.meters,
                  s.level.degrees,
                  s.trials,
                  s.successes,
                  s.successRate(),
                  s.median_error_m,
                  s.median_error_deg,
                  s.median_ms,
                  s.p95_ms,
                  s.median_cpu_ms,
                  optionalCount(v, &VerdictCounts::converged),
                  optionalCount(v, &VerdictCounts::wrong_converged),
                  optionalRate(v, &VerdictCounts::wrong_converged, s.trials),
                  optionalCount(v, &VerdictCounts::false_failures),
                  optionalRate(v, &VerdictCounts::false_failures, s.trials),
                  run.setup_seconds,
                  run.first_call_seconds * 1e3,
                  joined(s.pyramid, [](const PyramidLevelTime& p) { return p.resolution; }),
                  joined(s.pyramid, [](const PyramidLevelTime& p) { return p.mean_seconds * 1e3; }),
                  joined(s.pyramid, [](const PyramidLevelTime& p) { return p.mean_iterations; })});
  }
  table.write(path);
}

void writeTrialsCsv(const std::string& path, const std::string& dataset,
                    const std::vector<SystemRun>& runs, const std::vector<ErrorLevel>& levels) {
  // clang-format off
  apps::CsvTable table({"dataset", "system", "threads", "scan", "translation_m", "rotation_deg",
                        "trial", "error_m", "error_deg", "success", "converged", "failure",
                        "score", "matched_fraction", "ms", "cpu_ms", "first_call",
                        "start_x", "start_y", "start_z", "start_qw", "start_qx", "start_qy",
                        "start_qz", "x", "y", "z", "qw", "qx", "qy", "qz"});
  // clang-format on
  for (const SystemRun& run : runs)
    for (const Trial& t : run.trials) {
      const ErrorLevel& level = levels[t.start.level];
      const Eigen::Vector3d s = t.start.guess.translation(), p = t.attempt.pose.translation();
      const Eigen::Quaterniond sq(t.start.guess.linear()), pq(t.attempt.pose.linear());
      std::string failure = t.attempt.failure;
      std::replace(failure.begin(), failure.end(), ',', ';');  // one field, one line
      std::replace(failure.begin(), failure.end(), '\n', ' ');
      table.addRow({dataset,
                    run.label,
                    run.threads,
                    t.start.scan,
                    level.meters,
                    level.degrees,
                    t.start.trial,
                    t.error.meters,
                    t.error.degrees,
                    int(t.error.success()),
                    t.attempt.converged ? CsvCell(int(*t.attempt.converged)) : CsvCell(""),
                    failure,
                    optionalNumber(t.attempt.score),
                    optionalNumber(t.attempt.matched_fraction),
                    t.seconds * 1e3,
                    t.cpu_seconds * 1e3,
                    int(t.first_call),
                    s.x(),
                    s.y(),
                    s.z(),
                    sq.w(),
                    sq.x(),
                    sq.y(),
                    sq.z(),
                    p.x(),
                    p.y(),
                    p.z(),
                    pq.w(),
                    pq.x(),
                    pq.y(),
                    pq.z()});
    }
  table.write(path);
}

}  // namespace ndtom::regbench
