// The memory a map may take. Insertion, setCell() and the loaders check it before they
// allocate blocks, and refuse with MemoryBudgetError, the map unchanged, instead of letting a
// small input whose geometry is hostile or mistaken (a point at 6 km, a 1 mm resolution, a
// file of scattered cells) take gigabytes.
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>

namespace ndtom {

class MemoryBudgetError : public std::runtime_error {
 public:
  /// `what` says what needed the memory; the message adds the numbers.
  MemoryBudgetError(const std::string& what, uint64_t needed, uint64_t budget);
  uint64_t needed() const { return needed_; }  ///< bytes (at least)
  uint64_t budget() const { return budget_; }  ///< bytes

 private:
  uint64_t needed_, budget_;
};

/// A quarter of the machine's physical memory, and at most 512 MB: the default budget of a
/// map (see ScanOptions::memory_budget). The project's largest maps (60 lidar scans at
/// 0.1 m) take 65 MB.
uint64_t defaultMemoryBudget();

/// Smallest budget accepted (1 MB): below it not even an empty scan's buffers fit.
inline constexpr uint64_t kMinMemoryBudget = 1000000;

}  // namespace ndtom
