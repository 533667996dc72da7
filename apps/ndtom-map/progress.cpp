#include "progress.h"

#include <unistd.h>

#include <cstdio>
#include <string>

namespace ndtom::mapper {

Progress::Progress(bool enabled) : enabled_(enabled), terminal_(isatty(STDERR_FILENO) != 0) {}

void Progress::startPass(int pass, int passes, size_t scans) {
  pass_ = pass;
  passes_ = passes;
  scans_ = scans;
  done_ = points_ = 0;
  last_tenth_ = -1;
  start_ = last_print_ = std::chrono::steady_clock::now();
}

void Progress::update(size_t done, size_t points) {
  done_ = done;
  points_ = points;
  if (!enabled_) return;
  const auto now = std::chrono::steady_clock::now();
  if (terminal_) {
    if (std::chrono::duration<double>(now - last_print_).count() < 0.1) return;
  } else {
    const int tenth = scans_ > 0 ? int(10 * done_ / scans_) : 10;
    if (tenth == last_tenth_ || done_ == scans_) return;  // the final line comes at the end
    last_tenth_ = tenth;
  }
  last_print_ = now;
  print(false);
}

void Progress::finishPass() {
  if (enabled_) print(true);
}

void Progress::print(bool final_line) {
  const double elapsed =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  const double rate = elapsed > 0 ? double(points_) / elapsed : 0;
  const double left = done_ > 0 ? elapsed / double(done_) * double(scans_ - done_) : 0;
  std::string pass;
  if (passes_ > 1) pass = "pass " + std::to_string(pass_) + "/" + std::to_string(passes_) + " ";
  constexpr int kBarWidth = 30;
  const int filled = scans_ > 0 ? int(kBarWidth * done_ / scans_) : kBarWidth;
  const std::string bar =
      terminal_ ? "[" + std::string(filled, '#') + std::string(kBarWidth - filled, '.') + "] " : "";
  std::fprintf(stderr, "%s%s%s%zu/%zu scans, %.2f Mpoints/s, ", terminal_ ? "\r\033[K" : "",
               pass.c_str(), bar.c_str(), done_, scans_, rate * 1e-6);
  if (final_line)
    std::fprintf(stderr, "%.1f s\n", elapsed);
  else
    std::fprintf(stderr, "%.0f s left%s", left, terminal_ ? "" : "\n");
  std::fflush(stderr);
}

}  // namespace ndtom::mapper
