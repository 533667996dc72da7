// Where each system becomes real-time (paper Fig. 5): the finest resolution from which on its
// median time per scan stays within the sensor's scan period.
#pragma once

#include <string>
#include <vector>

#include "run_result.h"

namespace ndtom::bench {

/// One line per system of `dataset`, e.g. "octomap/t1: real time (<= 500 ms) from 0.2 m".
std::vector<std::string> realTimeThresholds(const std::vector<RunResult>& runs,
                                            const std::string& dataset, double period_ms);

}  // namespace ndtom::bench
