// Progress of a long loop on stderr: "[task] 12/60 steps, 3.1 steps/s, 15 s left".
// On a terminal the line is rewritten in place; in a log file each step gets a line.
#pragma once

#include <chrono>
#include <string>

namespace ndtom::eval {

class Progress {
 public:
  Progress(std::string task, size_t total, std::string unit = "scans");
  /// Call after each finished step.
  void step();
  /// Seconds since construction.
  double elapsed() const;

 private:
  std::string task_, unit_;
  size_t total_, done_ = 0;
  std::chrono::steady_clock::time_point start_;
  bool terminal_;
};

}  // namespace ndtom::eval
