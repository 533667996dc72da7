// Progress of the benchmark on stderr: run, scans done, rate and time left. Rewrites one line
// on a terminal; prints a line every few seconds otherwise (logs, ctest).
#pragma once

#include <chrono>
#include <string>

namespace ndtom::bench {

class Progress {
 public:
  explicit Progress(bool enabled);

  /// A new run: `title` names it (dataset, resolution, system); run `index` of `runs`.
  void startRun(const std::string& title, int index, int runs, size_t scans);
  /// After each scan: scans done in this run, insertion seconds and points so far.
  void update(size_t done, double insert_seconds, size_t points);
  void finishRun();

 private:
  void print(bool final_line);

  bool enabled_;
  bool terminal_;
  std::string title_;
  int index_ = 0, runs_ = 0;
  size_t scans_ = 0, done_ = 0, points_ = 0;
  double insert_seconds_ = 0;
  std::chrono::steady_clock::time_point run_start_, last_print_;
};

}  // namespace ndtom::bench
