// The benchmark's figure: success rate against the initial error, one line per system (its
// one-thread run), drawn with the programs' line plot (ndtom_apps/line_plot.h).
#pragma once

#include <string>
#include <vector>

#include "level_summary.h"

namespace ndtom::regbench {

/// Throws std::runtime_error naming the file if it cannot be written.
void writeSuccessPlot(const std::string& path, const std::string& dataset,
                      const std::vector<LevelSummary>& summaries,
                      const std::vector<ErrorLevel>& levels);

}  // namespace ndtom::regbench
