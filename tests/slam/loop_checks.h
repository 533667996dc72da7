// The loop candidates ndtom-slam checked, read from its summary ("loop_closure.checks"), for
// the tests that judge them against true or reference poses.
#pragma once

#include <string>
#include <vector>

#include "mapper/mapper_run.h"

namespace slam_test {

struct CheckedLoop {
  size_t older_scan = 0, newer_scan = 0;  ///< first scans of the two keyframes
  bool accepted = false;
};

inline std::vector<CheckedLoop> checkedLoops(const std::string& json) {
  std::vector<CheckedLoop> loops;
  for (size_t at = json.find("\"older_scan\":"); at != std::string::npos;
       at = json.find("\"older_scan\":", at + 1)) {
    const std::string check = json.substr(at, json.find('}', at) - at);
    loops.push_back({size_t(mapper_test::jsonNumber(check, "older_scan")),
                     size_t(mapper_test::jsonNumber(check, "newer_scan")),
                     check.find("\"accepted\": true") != std::string::npos});
  }
  return loops;
}

}  // namespace slam_test
