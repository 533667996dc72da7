// Scaling beyond the threads measured: each run's time split by stage into what runs on the
// calling thread alone and what runs in parallel regions (StageProfile), and the speed-up
// Amdahl's law predicts from the one-thread run's parallel fraction.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "run_result.h"

namespace ndtom::bench {

/// The same system on one thread ("ndtom-point/t2" -> "ndtom-point/t1"), same dataset and
/// resolution, with a stage profile; or nullptr.
const RunResult* oneThreadRun(const std::vector<RunResult>& runs, const RunResult& run);

/// p of `run`'s system: the one-thread run's time in parallel regions over its whole timed
/// time (the calls as the benchmark timed them: time outside the stages counts as serial).
std::optional<double> parallelFractionT1(const std::vector<RunResult>& runs, const RunResult& run);

/// Process CPU time of `run` over that of its one-thread run.
std::optional<double> cpuRatioVsT1(const std::vector<RunResult>& runs, const RunResult& run);

/// Markdown: per run and stage, serial, parallel-region wall and thread busy time per call.
std::string stagesTable(const std::vector<RunResult>& runs);
/// Markdown: per system and resolution, p, predicted S(2/4/8/16), the measured speed-ups and
/// CPU ratios of its multi-thread runs.
std::string amdahlTable(const std::vector<RunResult>& runs);

/// CSV, a row per run and stage, then one "(all)" row per run with the timed total (serial:
/// the total less the parallel regions). Throws std::runtime_error naming the file.
void writeStagesCsv(const std::string& path, const std::vector<RunResult>& runs);

}  // namespace ndtom::bench
