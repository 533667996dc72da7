// The CSV files: one row per system, threads and error level (--csv), and one row per
// registration with its start, final pose, errors, verdict and time (--trials-csv).
#pragma once

#include <string>
#include <vector>

#include "level_summary.h"
#include "system_run.h"

namespace ndtom::regbench {

/// Throw std::runtime_error naming the file if it cannot be written.
void writeLevelsCsv(const std::string& path, const std::string& dataset,
                    const std::vector<SystemRun>& runs, const std::vector<LevelSummary>& summaries);
void writeTrialsCsv(const std::string& path, const std::string& dataset,
                    const std::vector<SystemRun>& runs, const std::vector<ErrorLevel>& levels);

}  // namespace ndtom::regbench
