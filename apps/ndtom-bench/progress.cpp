#include "progress.h"

#include <unistd.h>

#include <cstdio>

namespace ndtom::bench {

Progress::Progress(bool enabled) : enabled_(enabled), terminal_(isatty(STDERR_FILENO) != 0) {}

void Progress::startRun(const std::string& title, int index, int runs, size_t scans) {
  title_ = title;
  index_ = index;
  runs_ = runs;
  scans_ = scans;
  done_ = points_ = 0;
  insert_seconds_ = 0;
  run_start_ = last_print_ = std::chrono::steady_clock::now();
}

void Progress::update(size_t done, double insert_seconds, size_t points) {
  done_ = done;
  insert_seconds_ = insert_seconds;
  points_ = points;
  const auto now = std::chrono::steady_clock::now();
  const double since = std::chrono::duration<double>(now - last_print_).count();
  if (since >= (terminal_ ? 0.2 : 5.0)) {
    print(false);
    last_print_ = now;
  }
}

void Progress::finishRun() {
  print(true);
}

void Progress::print(bool final_line) {
  if (!enabled_) return;
  // Wall time includes the untimed work (conversions, visit counting), so "left" is honest.
  const double wall =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - run_start_).count();
  const double per_scan_wall = done_ > 0 ? wall / double(done_) : 0;
  const double left = per_scan_wall * double(scans_ - done_);
  const double rate = insert_seconds_ > 0 ? double(done_) / insert_seconds_ : 0;
  const double mpts = insert_seconds_ > 0 ? double(points_) / insert_seconds_ * 1e-6 : 0;
  std::fprintf(stderr, "%s[run %d/%d] %s: %zu/%zu scans, %.1f scans/s, %.2f Mpts/s, %.0f s left%s",
               terminal_ ? "\r\033[K" : "", index_, runs_, title_.c_str(), done_, scans_, rate,
               mpts, left, terminal_ && !final_line ? "" : "\n");
  std::fflush(stderr);
}

}  // namespace ndtom::bench
