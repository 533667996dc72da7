// Where the time of scan insertions or registrations goes, stage by stage: the time on the
// calling thread alone, and the wall and per-thread busy time of the regions run on the worker
// threads. The library fills one when ScanOptions::profile or RegistrationOptions::profile
// points to it; ndtom-bench predicts speed-ups at more threads from it (Amdahl, see
// doc/benchmarks.md). It only observes: maps and poses are the same with or without one.
#pragma once

#include <algorithm>
#include <cstdint>
#include <string>
#include <vector>

namespace ndtom {

/// One named stage, summed over calls.
struct StageTimes {
  std::string name;
  uint64_t calls = 0;
  double wall_seconds = 0;           ///< the stage from start to end
  double parallel_wall_seconds = 0;  ///< of that, in regions run on the worker threads
  double busy_seconds = 0;           ///< those regions' task time, summed over threads
  uint64_t regions = 0;              ///< parallel regions run

  /// Time on the calling thread alone: what more threads leave as it is.
  double serialSeconds() const { return std::max(0.0, wall_seconds - parallel_wall_seconds); }
};

/// Filled on the thread that inserts or registers, unsynchronised: one profile per such
/// thread. A profiled call made inside another's stage counts in that stage's wall time too.
struct StageProfile {
  std::vector<StageTimes> stages;  ///< in the order first run

  /// The stage named `name`, added (zero) if it is not there yet.
  StageTimes& stage(const char* name) {
    for (StageTimes& s : stages)
      if (s.name == name) return s;
    stages.emplace_back();
    stages.back().name = name;
    return stages.back();
  }
  const StageTimes* find(const std::string& name) const {
    for (const StageTimes& s : stages)
      if (s.name == name) return &s;
    return nullptr;
  }
  double wallSeconds() const { return sum(&StageTimes::wall_seconds); }
  double parallelWallSeconds() const { return sum(&StageTimes::parallel_wall_seconds); }
  double busySeconds() const { return sum(&StageTimes::busy_seconds); }
  double serialSeconds() const {
    double s = 0;
    for (const StageTimes& t : stages) s += t.serialSeconds();
    return s;
  }
  void clear() { stages.clear(); }

 private:
  double sum(double StageTimes::*field) const {
    double s = 0;
    for (const StageTimes& t : stages) s += t.*field;
    return s;
  }
};

}  // namespace ndtom
