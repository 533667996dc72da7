#include "progress.h"

#include <unistd.h>

#include <cstdio>

namespace ndtom::eval {

Progress::Progress(std::string task, size_t total, std::string unit)
    : task_(std::move(task)),
      unit_(std::move(unit)),
      total_(total),
      start_(std::chrono::steady_clock::now()),
      terminal_(isatty(fileno(stderr)) != 0) {}

double Progress::elapsed() const {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
}

void Progress::step() {
  ++done_;
  const double seconds = elapsed();
  const double rate = seconds > 0 ? double(done_) / seconds : 0.0;
  const double left = rate > 0 ? double(total_ - done_) / rate : 0.0;
  std::fprintf(stderr, "%s[%s] %zu/%zu %s, %.2f %s/s, %.0f s left%s", terminal_ ? "\r" : "",
               task_.c_str(), done_, total_, unit_.c_str(), rate, unit_.c_str(), left,
               terminal_ && done_ < total_ ? "   " : "\n");
  if (done_ == total_) std::fprintf(stderr, "[%s] done in %.1f s\n", task_.c_str(), seconds);
  std::fflush(stderr);
}

}  // namespace ndtom::eval
