// Progress of a long loop on stderr, the same in every program:
//   "pass 2/3: [######........] 12/60 scans, 3.10 scans/s, 1.20 Mpoints/s, 15 s left"
// and, once all steps are done, "pass 2/3: 60/60 scans, 3.10 scans/s, ..., done in 19.4 s".
// On a terminal one line with a bar is rewritten in place (at most ten times a second); in a
// log (ctest, CI) a plain line is written at every tenth of the total.
#pragma once

#include <chrono>
#include <cstddef>
#include <optional>
#include <string>

namespace ndtom::apps {

/// Where a task stands, and the figures a progress line shows from it.
struct ProgressState {
  size_t done = 0, total = 0;
  size_t points = 0;          ///< points processed so far; 0: no points rate
  double elapsed = 0;         ///< wall seconds since the task started
  double rate_seconds = 0;    ///< seconds the rates are taken over (elapsed, or the timed part)

  /// At the pace so far (wall time per step); 0 before the first step and once done.
  double secondsLeft() const;
  double stepsPerSecond() const;   ///< 0 while no time has passed
  double pointsPerSecond() const;  ///< 0 while no time has passed
};

/// The text of a line (without "\r" or "\n"): `label` first if not empty, a bar of
/// `bar_width` characters if > 0, then the figures; the final line gives the total time
/// instead of the time left.
std::string progressText(const std::string& label, const std::string& unit,
                         const ProgressState& state, bool final_line, int bar_width = 0);

class Progress {
 public:
  /// Shows nothing if `enabled` is false (--quiet).
  explicit Progress(bool enabled = true);

  /// A new task of `total` steps counted in `unit`; `label` leads its lines ("pass 2/3").
  void start(std::string label, size_t total, std::string unit = "scans");
  /// After each step: steps done and points processed so far in this task. The final line
  /// comes when `done` reaches the total.
  void update(size_t done, size_t points = 0);
  /// The same where only part of the work is timed (a benchmark times insertion alone): the
  /// rates are over `timed_seconds`; the time left stays on wall time, which includes the rest.
  void update(size_t done, size_t points, double timed_seconds);
  /// One more step done, for loops without a counter.
  void step();
  /// The final line, if update() has not written it (fewer steps than announced).
  void finish();

 private:
  ProgressState state() const;
  void print(bool final_line);

  bool enabled_, terminal_;
  std::string label_, unit_;
  size_t total_ = 0, done_ = 0, points_ = 0;
  std::optional<double> timed_seconds_;
  int last_tenth_ = -1;
  bool finished_ = false;
  std::chrono::steady_clock::time_point start_, last_print_;
};

}  // namespace ndtom::apps
