// Timing of a profiled call's stages (StageProfile): private to the library.
#pragma once

#include <cstddef>

#include "ndtom/support/stage_profile.h"
#include "support/elapsed.h"

namespace ndtom {

/// The stage the calling thread is timing, if any: WorkerPool::run adds its regions to it.
/// Per thread, so that no pool needs to be told (a pyramid's own pool is timed too), and a
/// region's tasks, which run with none, record nothing twice. By index: a nested profiled
/// call may add stages, moving the vector.
struct OpenStage {
  StageProfile* profile = nullptr;
  size_t index = 0;
  StageTimes* get() const { return profile ? &profile->stages[index] : nullptr; }
};
inline thread_local OpenStage t_open_stage;

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
      StageTimes& stage = profile_->stage(name);
      open_ = size_t(&stage - profile_->stages.data());
    } catch (...) {  // out of memory: the call goes on unprofiled
      profile_ = nullptr;
      return;
    }
    ++profile_->stages[open_].calls;
    outer_ = t_open_stage;
    t_open_stage = {profile_, open_};
    start_ = now;
  }
  void stop() noexcept {
    if (profile_) close(Clock::now());
  }

 private:
  static constexpr size_t kNone = size_t(-1);

  void close(Clock::time_point now) noexcept {
    if (open_ == kNone) return;
    profile_->stages[open_].wall_seconds += std::chrono::duration<double>(now - start_).count();
    t_open_stage = outer_;
    open_ = kNone;
  }

  StageProfile* profile_;
  size_t open_ = kNone;  ///< index of the open stage in profile_->stages
  OpenStage outer_;
  Clock::time_point start_;
};

/// Work that stays on one thread by design (it only borrows a pool's interface): its
/// time remains its stage's serial time.
class SerialRegion {
 public:
  SerialRegion() noexcept : outer_(t_open_stage) { t_open_stage = {}; }
  ~SerialRegion() { t_open_stage = outer_; }
  SerialRegion(const SerialRegion&) = delete;
  SerialRegion& operator=(const SerialRegion&) = delete;

 private:
  OpenStage outer_;
};

}  // namespace ndtom
