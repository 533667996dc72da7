#include "targets.h"

#include <cmath>
#include <cstdarg>
#include <cstdio>

#include "ndtom_apps/statistics.h"

namespace ndtom::regbench {

namespace {

constexpr double kMinSuccessUpTo2m = 0.99;  // every level up to 2 m / 20°, pooled
constexpr double kMinSuccessAt3m = 0.95;
constexpr double kMaxMedianErrorM = 0.02, kMaxMedianErrorDeg = 0.1;
constexpr double kMaxWrongConverged = 0.01;  // over all registrations
constexpr double kMaxMedianMs = 100;

std::string line(bool pass, const std::string& label, const char* format, ...)
    __attribute__((format(printf, 3, 4)));

std::string line(bool pass, const std::string& label, const char* format, ...) {
  char text[300];
  va_list args;
  va_start(args, format);
  std::vsnprintf(text, sizeof text, format, args);
  va_end(args);
  return std::string(pass ? "PASS " : "FAIL ") + label + ": " + text;
}

struct Pooled {
  int trials = 0, successes = 0;
};

Pooled pool(const std::vector<const LevelSummary*>& levels, double lo_m, double hi_m) {
  Pooled p;
  for (const LevelSummary* s : levels)
    if (s->level.meters >= lo_m - 1e-9 && s->level.meters <= hi_m + 1e-9) {
      p.trials += s->trials;
      p.successes += s->successes;
    }
  return p;
}

std::string successLine(const std::string& label, const char* where, const Pooled& p,
                        double min_rate) {
  if (p.trials == 0) return "SKIP " + label + ": success " + where + " (no such error level run)";
  return line(p.successes >= min_rate * p.trials, label,
              "success %s %d/%d (%.1f %%, target >= %g %%)", where, p.successes, p.trials,
              100.0 * p.successes / p.trials, 100 * min_rate);
}

std::vector<std::string> checkRun(const SystemRun& run,
                                  const std::vector<const LevelSummary*>& levels) {
  std::vector<std::string> out;
  const std::string& label = run.label;
  out.push_back(successLine(label, "up to 2 m / 20°", pool(levels, 0, 2.0), kMinSuccessUpTo2m));
  out.push_back(successLine(label, "at 3 m / 30°", pool(levels, 3.0, 3.0), kMinSuccessAt3m));

  std::vector<double> meters, degrees;
  int wrong = 0;
  for (const Trial& t : run.trials) {
    if (t.error.success()) {
      meters.push_back(t.error.meters);
      degrees.push_back(t.error.degrees);
    }
    wrong += t.attempt.converged.value_or(false) && !t.error.success();
  }
  if (meters.empty()) {
    out.push_back(line(false, label, "median error of the successes: there is no success"));
  } else {
    const double m = apps::quantile(meters, 0.5), d = apps::quantile(degrees, 0.5);
    out.push_back(line(m <= kMaxMedianErrorM && d <= kMaxMedianErrorDeg, label,
                       "median error of the successes %.2f cm / %.3f° (target <= 2 cm / 0.1°)",
                       m * 100, d));
  }
  const int n = int(run.trials.size());
  out.push_back(line(wrong <= kMaxWrongConverged * n, label,
                     "converged but wrong %d/%d (%.1f %%, target <= 1 %%)", wrong, n,
                     n ? 100.0 * wrong / n : 0.0));
  // On one thread CPU time is the time the registration took whatever else ran on the
  // machine; wall time beside it (see doc/registration/benchmark.md).
  const OverallTimes t = overallTimes(run);
  if (!std::isnan(t.median_cpu_ms))
    out.push_back(line(t.median_cpu_ms <= kMaxMedianMs, label,
                       "median time %.1f ms CPU (%.1f ms wall) per registration over all levels, "
                       "pyramid cached (target <= 100 ms)",
                       t.median_cpu_ms, t.median_ms));
  return out;
}

}  // namespace

std::vector<std::string> checkTargets(const std::vector<SystemRun>& runs,
                                      const std::vector<LevelSummary>& summaries) {
  std::vector<std::string> out;
  for (const SystemRun& run : runs) {
    if (!isNdtom(run.kind) || run.threads != 1) continue;
    std::vector<const LevelSummary*> levels;
    for (const LevelSummary& s : summaries)
      if (s.label == run.label) levels.push_back(&s);
    for (std::string& l : checkRun(run, levels)) out.push_back(std::move(l));
  }
  return out;
}

}  // namespace ndtom::regbench
