// One system over every start: the timed registrations, their errors to the reference and
// the system's setup and first-call times.
#pragma once

#include <string>
#include <vector>

#include "ndtom_apps/progress.h"
#include "pose_error.h"
#include "regbench_options.h"
#include "registration_system.h"
#include "start_plan.h"

namespace ndtom::regbench {

struct Trial {
  Start start;
  Attempt attempt;
  PoseError error;          ///< of attempt.pose to the reference
  double seconds = 0;       ///< wall time of align()
  double cpu_seconds = 0;   ///< process CPU time of align() (all threads)
  bool first_call = false;  ///< the system's first align(): left out of the time figures
};

struct SystemRun {
  SystemKind kind = SystemKind::NdtomP2D;
  std::string label;     ///< "ndtom-p2d/t1", "mrpt-icp", ...
  std::string settings;  ///< RegistrationSystem::settings()
  int threads = 1;
  double setup_seconds = 0;       ///< making the system: its map from the map scans
  double first_call_seconds = 0;  ///< the first align(): builds what the system caches
  std::vector<Trial> trials;      ///< in the order of the starts
};

/// Registers every held-out scan from each of `starts` (sensor frame scans from `scans`,
/// indexed by scan number; `held_out` gives the order the system took them in), timing each
/// align() call, and measures the errors against `poses`. Progress per registration.
SystemRun runSystem(RegistrationSystem& system, const std::vector<Start>& starts,
                    const std::vector<int>& held_out, const std::vector<Eigen::Isometry3d>& poses,
                    apps::Progress& progress);

}  // namespace ndtom::regbench
