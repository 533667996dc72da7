#include "system_run.h"

#include <algorithm>
#include <chrono>

#include "ndtom_apps/process_clock.h"

namespace ndtom::regbench {

SystemRun runSystem(RegistrationSystem& system, const std::vector<Start>& starts,
                    const std::vector<int>& held_out, const std::vector<Eigen::Isometry3d>& poses,
                    apps::Progress& progress) {
  SystemRun run;
  run.label = system.label();
  run.settings = system.settings();
  double timed = 0;
  for (const Start& start : starts) {
    const auto slot = std::find(held_out.begin(), held_out.end(), start.scan) - held_out.begin();
    Trial trial;
    trial.start = start;
    trial.first_call = run.trials.empty();
    const double cpu = apps::processCpuSeconds();
    const auto t0 = std::chrono::steady_clock::now();
    trial.attempt = system.align(size_t(slot), start.guess);
    trial.seconds = apps::secondsSince(t0);
    trial.cpu_seconds = apps::processCpuSeconds() - cpu;
    trial.error = poseError(trial.attempt.pose, poses.at(size_t(start.scan)));
    if (trial.first_call) run.first_call_seconds = trial.seconds;
    timed += trial.seconds;
    run.trials.push_back(std::move(trial));
    progress.update(run.trials.size(), 0, timed);
  }
  progress.finish();
  return run;
}

}  // namespace ndtom::regbench
