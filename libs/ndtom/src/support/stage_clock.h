// Timing of a profiled call's stages (StageProfile): private to the library.
#pragma once

#include "ndtom/support/stage_profile.h"
#include "support/elapsed.h"

namespace ndtom {

/// The stage the calling thread is timing, if any: WorkerPool::run adds its regions to it.
/// Per thread, so that no pool needs to be told (a pyramid's own pool is timed too), and a
/// region's tasks, which run with none, record nothing twice.
inline thread_local StageTimes* t_open_stage = nullptr;

/// Times a call's stages one after the other: next("sort") ends the stage before it; the
/// destructor ends the last. Without a profile it does nothing but check the pointer.
class StageClock {
 public:
  explicit StageClock(StageProfile* profile) noexcept : profile_(profile) {}
  ~StageClock() { stop(); }
  StageClock(const StageClock&) = delete;
  StageClock& operator=(const StageClock&) = delete;

  void next(const char* name) noexcept {
    if (!profile_) return;
    const Clock::time_point now = Clock::now();
    close(now);
    try {
      open_ = &profile_->stage(name);
    } catch (...) {  // out of memory: the call goes on unprofiled
      profile_ = nullptr;
      return;
    }
    ++open_->calls;
    outer_ = t_open_stage;
    t_open_stage = open_;
    start_ = now;
  }
  void stop() noexcept {
    if (profile_) close(Clock::now());
  }

 private:
  void close(Clock::time_point now) noexcept {
    if (!open_) return;
    open_->wall_seconds += std::chrono::duration<double>(now - start_).count();
    t_open_stage = outer_;
    open_ = nullptr;
  }

  StageProfile* profile_;
  StageTimes* open_ = nullptr;
  StageTimes* outer_ = nullptr;
  Clock::time_point start_;
};

/// Work that stays on one thread by design (it only borrows a pool's interface): its
/// time remains its stage's serial time.
class SerialRegion {
 public:
  SerialRegion() noexcept : outer_(t_open_stage) { t_open_stage = nullptr; }
  ~SerialRegion() { t_open_stage = outer_; }
  SerialRegion(const SerialRegion&) = delete;
  SerialRegion& operator=(const SerialRegion&) = delete;

 private:
  StageTimes* outer_;
};

}  // namespace ndtom
