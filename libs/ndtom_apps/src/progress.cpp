#include "ndtom_apps/progress.h"

#include <unistd.h>

#include <algorithm>
#include <cstdio>

#include "ndtom_apps/process_clock.h"

namespace ndtom::apps {
namespace {

constexpr int kBarWidth = 30;
constexpr double kTerminalPeriod = 0.1;  // s between rewrites of the line on a terminal

}  // namespace

double ProgressState::secondsLeft() const {
  if (done == 0 || done >= total) return 0;
  return elapsed / double(done) * double(total - done);
}

double ProgressState::stepsPerSecond() const {
  return rate_seconds > 0 ? double(done) / rate_seconds : 0;
}

double ProgressState::pointsPerSecond() const {
  return rate_seconds > 0 ? double(points) / rate_seconds : 0;
}

std::string progressText(const std::string& label, const std::string& unit,
                         const ProgressState& state, bool final_line, int bar_width) {
  std::string text = label.empty() ? "" : label + ": ";
  if (bar_width > 0) {
    const size_t shown = std::min(state.done, state.total);
    const int filled = state.total > 0 ? int(size_t(bar_width) * shown / state.total) : bar_width;
    text += "[" + std::string(filled, '#') + std::string(bar_width - filled, '.') + "] ";
  }
  char buffer[256];
  std::snprintf(buffer, sizeof buffer, "%zu/%zu %s, %.2f %s/s", state.done, state.total,
                unit.c_str(), state.stepsPerSecond(), unit.c_str());
  text += buffer;
  if (state.points > 0) {
    std::snprintf(buffer, sizeof buffer, ", %.2f Mpoints/s", state.pointsPerSecond() * 1e-6);
    text += buffer;
  }
  if (final_line)
    std::snprintf(buffer, sizeof buffer, ", done in %.1f s", state.elapsed);
  else
    std::snprintf(buffer, sizeof buffer, ", %.0f s left", state.secondsLeft());
  return text + buffer;
}

Progress::Progress(bool enabled) : enabled_(enabled), terminal_(isatty(STDERR_FILENO) != 0) {}

void Progress::start(std::string label, size_t total, std::string unit) {
  label_ = std::move(label);
  unit_ = std::move(unit);
  total_ = total;
  done_ = points_ = 0;
  timed_seconds_.reset();
  last_tenth_ = -1;
  finished_ = false;
  start_ = last_print_ = std::chrono::steady_clock::now();
}

void Progress::update(size_t done, size_t points) {
  done_ = done;
  points_ = points;
  if (!enabled_ || finished_) return;
  if (done_ >= total_) return finish();
  const auto now = std::chrono::steady_clock::now();
  if (terminal_) {
    if (std::chrono::duration<double>(now - last_print_).count() < kTerminalPeriod) return;
  } else {
    const int tenth = int(10 * done_ / total_);
    if (tenth == last_tenth_) return;
    last_tenth_ = tenth;
  }
  last_print_ = now;
  print(false);
}

void Progress::update(size_t done, size_t points, double timed_seconds) {
  timed_seconds_ = timed_seconds;
  update(done, points);
}

void Progress::step() {
  update(done_ + 1, points_);
}

void Progress::finish() {
  if (!enabled_ || finished_) return;
  finished_ = true;
  print(true);
}

ProgressState Progress::state() const {
  ProgressState s;
  s.done = done_;
  s.total = total_;
  s.points = points_;
  s.elapsed = secondsSince(start_);
  s.rate_seconds = timed_seconds_.value_or(s.elapsed);
  return s;
}

void Progress::print(bool final_line) {
  const std::string text =
      progressText(label_, unit_, state(), final_line, terminal_ ? kBarWidth : 0);
  // On a terminal: back to the line's start and clear it; a newline only after the last one.
  std::fprintf(stderr, "%s%s%s", terminal_ ? "\r\033[K" : "", text.c_str(),
               terminal_ && !final_line ? "" : "\n");
  std::fflush(stderr);
}

}  // namespace ndtom::apps
