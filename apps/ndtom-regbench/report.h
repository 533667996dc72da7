// The summary's Markdown tables (they paste into doc/registration/).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "level_summary.h"
#include "system_run.h"

namespace ndtom::regbench {

/// For a run with threads > 1: whether every pose equals that of the same system on one
/// thread, start by start; empty when there is no such run.
std::optional<bool> samePosesAsOneThread(const std::vector<SystemRun>& runs, const SystemRun& run);

/// One row per system: setup, first call, time over all registrations, settings.
std::string systemsTable(const std::vector<SystemRun>& runs);
/// One row per system, threads and error level: success, accuracy, time, verdicts.
std::string levelsTable(const std::vector<LevelSummary>& summaries);
/// Successes out of trials, one row per system and one column per error level.
std::string successMatrix(const std::vector<LevelSummary>& summaries,
                          const std::vector<ErrorLevel>& levels);
/// NdtRegistration's mean time and Newton steps per pyramid level, per error level, their sum
/// and the mean time of the whole call (first call left out): the difference is spent
/// outside the levels.
std::string pyramidTable(const std::vector<LevelSummary>& summaries);
/// Every registration whose verdict disagrees with the reference (converged but wrong, or
/// right but reported failed), for the systems that give a verdict; empty if none does.
std::string verdictTable(const std::vector<SystemRun>& runs, const std::vector<ErrorLevel>& levels);

}  // namespace ndtom::regbench
