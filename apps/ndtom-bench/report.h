// The summary tables (Markdown, so they paste into doc/benchmarks.md) and the CSV file.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "run_result.h"

namespace ndtom::bench {

/// Median time per scan of `run` divided by that of `other_label` in the same dataset and
/// resolution (same process, same run): empty if that system was not run. Wall-clock time,
/// or process CPU time if `cpu_time`.
std::optional<double> timeRatio(const std::vector<RunResult>& runs, const RunResult& run,
                                const std::string& other_label, bool cpu_time = false);

/// For threads > 1: the same ray mode's one-thread total insertion time over this run's
/// (separate runs, as timed by runSystem); empty otherwise.
std::optional<double> oneThreadSpeedup(const std::vector<RunResult>& runs, const RunResult& run);

/// One row per run: times, rates, memory, cells and the ratios to OctoMap and the 3D grid.
std::string resultsTable(const std::vector<RunResult>& runs);
/// One row per NDT-OM speed-up: identity to one thread, distance to the exact path.
std::string comparisonTable(const std::vector<RunResult>& runs);

/// Throws std::runtime_error naming the file if it cannot be written.
void writeCsv(const std::string& path, const std::vector<RunResult>& runs);

}  // namespace ndtom::bench
