// The targets the NDT-OM systems are judged on (issue #15), on one thread at the map's
// resolution with the pyramid cached: success >= 99 % up to 2 m / 20° and >= 95 % at
// 3 m / 30°; median error of the successes <= 2 cm and 0.1°; converged-but-wrong <= 1 %;
// median time per registration <= 100 ms (process CPU time: on a shared machine the wall
// time also counts the other processes).
#pragma once

#include <string>
#include <vector>

#include "level_summary.h"
#include "system_run.h"

namespace ndtom::regbench {

/// "PASS ..." / "FAIL ..." / "SKIP ..." lines, per NDT-OM system run on one thread.
std::vector<std::string> checkTargets(const std::vector<SystemRun>& runs,
                                      const std::vector<LevelSummary>& summaries);

}  // namespace ndtom::regbench
