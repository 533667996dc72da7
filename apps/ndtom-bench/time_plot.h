// The paper's Fig. 5 for our systems: median time per scan (bar up to p95) against the
// resolution, log-log, one line per system, drawn with the programs' line plot
// (ndtom_apps/line_plot.h).
#pragma once

#include <string>
#include <vector>

#include "run_result.h"

namespace ndtom::bench {

/// Plots the runs of `dataset`, with a dashed horizontal line at each of `real_time_ms`
/// (scan periods); throws std::runtime_error naming the file if it cannot be
/// written.
void writeTimePlot(const std::string& path, const std::vector<RunResult>& runs,
                   const std::string& dataset, const std::vector<double>& real_time_ms = {});

}  // namespace ndtom::bench
