// Amdahl's law: the speed-up more threads can give work of which a measured fraction runs in
// parallel regions (the rest, on one thread, stays as long).
#pragma once

namespace ndtom::bench {

/// Thread counts the benchmark predicts for, beyond the 1-2 it measures on a small machine.
inline constexpr int kPredictedThreads[] = {2, 4, 8, 16};

/// S(n) = 1 / ((1 - p) + p / n). Throws std::invalid_argument unless p is in [0, 1] and
/// n >= 1 (both finite).
double amdahlSpeedup(double parallel_fraction, double threads);

/// CPU time at n threads over one thread's when idle workers spin through every serial
/// stretch (the pool spins 200 µs before it sleeps, longer than most of a scan's serial
/// gaps): n (1 - p) + p, i.e. n threads busy for the whole of S(n)'s shorter wall time. An
/// upper bound for short gaps; it ignores imbalance inside regions. Throws as amdahlSpeedup.
double spinningCpuRatio(double parallel_fraction, double threads);

/// p: the time in parallel regions over the whole time, both of a one-thread run; clamped to
/// [0, 1] (clocks read apart can put the first a hair past the second). Throws
/// std::invalid_argument if either is negative or not finite, or the total is not > 0.
double parallelFraction(double parallel_seconds, double total_seconds);

}  // namespace ndtom::bench
