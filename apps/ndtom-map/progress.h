// Progress of the mapping on stderr: scans done of total, points per second, time left.
// A bar rewritten in place on a terminal; a plain line at every tenth otherwise (logs, CI).
#pragma once

#include <chrono>
#include <cstddef>

namespace ndtom::mapper {

class Progress {
 public:
  /// Draws nothing if `enabled` is false (--quiet).
  explicit Progress(bool enabled);

  void startPass(int pass, int passes, size_t scans);
  /// After each scan: scans done in this pass and points read so far in it.
  void update(size_t done, size_t points);
  void finishPass();

 private:
  void print(bool final_line);

  bool enabled_, terminal_;
  int pass_ = 0, passes_ = 0;
  size_t scans_ = 0, done_ = 0, points_ = 0;
  int last_tenth_ = -1;
  std::chrono::steady_clock::time_point start_, last_print_;
};

}  // namespace ndtom::mapper
