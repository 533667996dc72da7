#include "level_summary.h"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <numeric>

#include "ndtom_apps/statistics.h"

namespace ndtom::regbench {

namespace {

double medianOrNan(const std::vector<double>& values) {
  return values.empty() ? NAN : apps::quantile(values, 0.5);
}

VerdictCounts countVerdicts(const std::vector<const Trial*>& trials) {
  VerdictCounts v;
  for (const Trial* t : trials) {
    const bool converged = t->attempt.converged.value_or(false);
    v.converged += converged;
    v.wrong_converged += converged && !t->error.success();
    v.false_failures += !converged && t->error.success();
  }
  return v;
}

std::vector<PyramidLevelTime> pyramidTimes(const std::vector<const Trial*>& trials) {
  std::vector<PyramidLevelTime> out;
  for (const Trial* t : trials) {
    if (out.size() < t->attempt.levels.size()) out.resize(t->attempt.levels.size());
    for (size_t l = 0; l < t->attempt.levels.size(); ++l) {
      out[l].resolution = t->attempt.levels[l].resolution;
      out[l].mean_seconds += t->attempt.levels[l].seconds / double(trials.size());
      out[l].mean_iterations += t->attempt.levels[l].iterations / double(trials.size());
    }
  }
  return out;
}

}  // namespace

std::vector<LevelSummary> summarize(const SystemRun& run, const std::vector<ErrorLevel>& levels) {
  std::vector<LevelSummary> out;
  for (size_t l = 0; l < levels.size(); ++l) {
    std::vector<const Trial*> trials;
    for (const Trial& t : run.trials)
      if (t.start.level == l) trials.push_back(&t);
    LevelSummary s;
    s.label = run.label;
    s.kind = run.kind;
    s.threads = run.threads;
    s.level = levels[l];
    s.trials = int(trials.size());
    std::vector<double> meters, degrees, ms, cpu_ms;
    bool has_verdicts = false;
    for (const Trial* t : trials) {
      has_verdicts |= t->attempt.converged.has_value();
      if (t->error.success()) {
        ++s.successes;
        meters.push_back(t->error.meters);
        degrees.push_back(t->error.degrees);
      }
      if (t->first_call) continue;
      ms.push_back(t->seconds * 1e3);
      cpu_ms.push_back(t->cpu_seconds * 1e3);
    }
    s.median_error_m = medianOrNan(meters);
    s.median_error_deg = medianOrNan(degrees);
    s.median_ms = medianOrNan(ms);
    s.p95_ms = ms.empty() ? NAN : apps::quantile(ms, 0.95);
    s.median_cpu_ms = medianOrNan(cpu_ms);
    s.mean_ms = ms.empty() ? NAN : std::accumulate(ms.begin(), ms.end(), 0.0) / double(ms.size());
    if (has_verdicts) s.verdicts = countVerdicts(trials);
    std::vector<const Trial*> cached;  // the pyramid built: as the times, the first call left out
    std::copy_if(trials.begin(), trials.end(), std::back_inserter(cached),
                 [](const Trial* t) { return !t->first_call; });
    s.pyramid = pyramidTimes(cached);
    out.push_back(std::move(s));
  }
  return out;
}

OverallTimes overallTimes(const SystemRun& run) {
  std::vector<double> ms, cpu_ms;
  for (const Trial& t : run.trials) {
    if (t.first_call) continue;
    ms.push_back(t.seconds * 1e3);
    cpu_ms.push_back(t.cpu_seconds * 1e3);
  }
  if (ms.empty()) return {NAN, NAN, NAN};
  return {apps::quantile(ms, 0.5), apps::quantile(ms, 0.95), apps::quantile(cpu_ms, 0.5)};
}

}  // namespace ndtom::regbench
