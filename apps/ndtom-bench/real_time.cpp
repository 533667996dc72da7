#include "real_time.h"

#include <algorithm>
#include <cstdio>
#include <map>

namespace ndtom::bench {

std::vector<std::string> realTimeThresholds(const std::vector<RunResult>& runs,
                                            const std::string& dataset, double period_ms) {
  std::map<std::string, std::vector<const RunResult*>> series;  // label -> its runs
  std::vector<std::string> order;
  for (const RunResult& r : runs) {
    if (r.dataset != dataset || r.scan_seconds.empty()) continue;
    if (!series.count(r.label)) order.push_back(r.label);
    series[r.label].push_back(&r);
  }
  std::vector<std::string> lines;
  for (const std::string& label : order) {
    auto& s = series[label];
    std::sort(s.begin(), s.end(),
              [](const RunResult* a, const RunResult* b) { return a->resolution < b->resolution; });
    // Walk from the coarsest resolution down while the runs stay within the period.
    const RunResult* finest = nullptr;
    for (auto it = s.rbegin(); it != s.rend() && (*it)->medianSeconds() * 1e3 <= period_ms; ++it)
      finest = *it;
    char line[200];
    if (!finest)
      std::snprintf(line, sizeof line, "%s: not real time (<= %g ms) at any resolution run",
                    label.c_str(), period_ms);
    else
      std::snprintf(line, sizeof line, "%s: real time (<= %g ms) from %g m (%.0f ms)%s",
                    label.c_str(), period_ms, finest->resolution, finest->medianSeconds() * 1e3,
                    finest == s.front() ? ", the finest resolution run" : "");
    lines.push_back(line);
  }
  return lines;
}

}  // namespace ndtom::bench
