#include "report.h"

#include <cmath>
#include <cstdio>

namespace ndtom::regbench {

namespace {

/// printf of one number; "-" for NaN (no sample).
std::string number(const char* format, double value) {
  if (std::isnan(value)) return "-";
  char text[64];
  std::snprintf(text, sizeof text, format, value);
  return text;
}

std::string fraction(int part, int whole) {
  return std::to_string(part) + "/" + std::to_string(whole) +
         number(" (%.0f %%)", whole > 0 ? 100.0 * part / whole : NAN);
}

const SystemRun* oneThreadRun(const std::vector<SystemRun>& runs, const SystemRun& run) {
  for (const SystemRun& r : runs)
    if (r.kind == run.kind && r.threads == 1) return &r;
  return nullptr;
}

}  // namespace

std::optional<bool> samePosesAsOneThread(const std::vector<SystemRun>& runs, const SystemRun& run) {
  const SystemRun* one = run.threads > 1 ? oneThreadRun(runs, run) : nullptr;
  if (!one || one->trials.size() != run.trials.size()) return std::nullopt;
  for (size_t i = 0; i < run.trials.size(); ++i)
    if (run.trials[i].attempt.pose.matrix() != one->trials[i].attempt.pose.matrix()) return false;
  return true;
}

std::string systemsTable(const std::vector<SystemRun>& runs) {
  std::string out =
      "| system | threads | setup (s) | first call (ms) | median ms | p95 ms | median CPU ms | "
      "same poses as one thread | settings |\n|---|---:|---:|---:|---:|---:|---:|---|---|\n";
  for (const SystemRun& r : runs) {
    const OverallTimes t = overallTimes(r);
    const std::optional<bool> same = samePosesAsOneThread(runs, r);
    out += "| " + r.label + " | " + std::to_string(r.threads) + " | " +
           number("%.2f", r.setup_seconds) + " | " + number("%.0f", r.first_call_seconds * 1e3) +
           " | " + number("%.1f", t.median_ms) + " | " + number("%.1f", t.p95_ms) + " | " +
           number("%.1f", t.median_cpu_ms) + " | " + (same ? (*same ? "yes" : "NO") : "-") + " | " +
           r.settings + " |\n";
  }
  return out;
}

std::string levelsTable(const std::vector<LevelSummary>& summaries) {
  std::string out =
      "| system | initial error | success | median error of successes (cm / °) | median ms | "
      "p95 ms | median CPU ms | converged but wrong | right but reported failed |\n"
      "|---|---|---:|---:|---:|---:|---:|---:|---:|\n";
  for (const LevelSummary& s : summaries) {
    std::string wrong = "-", missed = "-";
    if (s.verdicts) {
      wrong = fraction(s.verdicts->wrong_converged, s.trials);
      missed = fraction(s.verdicts->false_failures, s.trials);
    }
    out += "| " + s.label + " | " + s.level.label() + " | " + fraction(s.successes, s.trials) +
           " | " + number("%.2f", s.median_error_m * 100) + " / " +
           number("%.3f", s.median_error_deg) + " | " + number("%.1f", s.median_ms) + " | " +
           number("%.1f", s.p95_ms) + " | " + number("%.1f", s.median_cpu_ms) + " | " + wrong +
           " | " + missed + " |\n";
  }
  return out;
}

std::string successMatrix(const std::vector<LevelSummary>& summaries,
                          const std::vector<ErrorLevel>& levels) {
  std::string out = "| system |", rule = "|---|";
  for (const ErrorLevel& l : levels) {
    out += " " + l.label() + " |";
    rule += "---:|";
  }
  out += "\n" + rule + "\n";
  std::string row_label;
  for (const LevelSummary& s : summaries) {
    if (s.label != row_label) {
      if (!row_label.empty()) out += "\n";
      row_label = s.label;
      out += "| " + s.label + " |";
    }
    out += " " + std::to_string(s.successes) + "/" + std::to_string(s.trials) + " |";
  }
  return out + "\n";
}

std::string pyramidTable(const std::vector<LevelSummary>& summaries) {
  std::string header, out;
  for (const LevelSummary& s : summaries) {
    if (s.pyramid.empty()) continue;
    if (header.empty()) {
      header = "| system | initial error |";
      std::string rule = "|---|---|";
      for (const PyramidLevelTime& p : s.pyramid) {
        header += number(" %g m |", p.resolution);
        rule += "---:|";
      }
      out = header + " all levels | whole call |\n" + rule + "---:|---:|\n";
    }
    out += "| " + s.label + " | " + s.level.label() + " |";
    double total = 0;
    for (const PyramidLevelTime& p : s.pyramid) {
      out += " " + number("%.1f", p.mean_seconds * 1e3) + " ms, " +
             number("%.1f", p.mean_iterations) + " |";
      total += p.mean_seconds;
    }
    out += " " + number("%.1f", total * 1e3) + " ms | " + number("%.1f", s.mean_ms) + " ms |\n";
  }
  return out;
}

std::string verdictTable(const std::vector<SystemRun>& runs,
                         const std::vector<ErrorLevel>& levels) {
  std::string out;
  bool any_verdict = false;
  for (const SystemRun& r : runs)
    for (const Trial& t : r.trials) {
      if (!t.attempt.converged) continue;
      any_verdict = true;
      if (*t.attempt.converged == t.error.success()) continue;
      out += "| " + r.label + " | " + std::to_string(t.start.scan) + " | " +
             levels[t.start.level].label() + " | " + std::to_string(t.start.trial) + " | " +
             number("%.3f", t.error.meters) + " / " + number("%.2f", t.error.degrees) + " | " +
             (*t.attempt.converged ? "**converged, wrong**" : "failed, right") + " | " +
             number("%.3f", t.attempt.matched_fraction.value_or(NAN)) + " | " +
             (t.attempt.failure.empty() ? "-" : t.attempt.failure) + " |\n";
    }
  if (!any_verdict) return "";
  if (out.empty()) return "Every verdict agrees with the reference.\n";
  return "| system | scan | initial error | trial | final error (m / °) | verdict | matched "
         "fraction | failure reported |\n|---|---:|---|---:|---:|---|---:|---|\n" +
         out;
}

}  // namespace ndtom::regbench
