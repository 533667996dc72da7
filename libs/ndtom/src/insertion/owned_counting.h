// The free-space walker of a distributed build's process (OwnedRayWalk): counts as
// CountingWalker does, but only in blocks of the tiles this process owns; other blocks are
// never added to the table, so they never reach the map. Private to the library.
#pragma once

#include <cstdint>

#include "../scan_counts.h"
#include "ndtom/tile_ownership.h"

namespace ndtom {

class OwnedCountingWalker {
 public:
  OwnedCountingWalker(ScanCounts& counts, const TileOwnership& owned)
      : counts_(&counts), owned_(&owned) {}
  void setWeight(uint32_t w) { weight_ = w; }
  size_t visits() const { return visits_; }

  void start(const CellIndex& c) {
    cell_ = c;
    enterBlock();
  }

  template <int Axis>
  void move(int32_t step) {
    int32_t& coordinate = cell_[Axis];
    coordinate += step;
    constexpr int32_t kMask = kBlockEdge - 1;
    if ((coordinate & kMask) == (step > 0 ? 0 : kMask)) {
      enterBlock();
    } else {
      offset_ += step * (1 << (Axis * kBlockLog2));
    }
  }

  bool visit() {
    if (block_) {
      block_->count[size_t(offset_)] += weight_;
      ++visits_;
    }
    return true;
  }

 private:
  void enterBlock() {
    const CellIndex b = blockOf(cell_);
    block_ = owned_->ownsBlock(b) ? &counts_->blockAt(b) : nullptr;
    offset_ = offsetInBlock(cell_);
  }

  ScanCounts* counts_;
  const TileOwnership* owned_;
  CellIndex cell_;
  CountBlock* block_ = nullptr;  ///< null outside owned tiles
  int32_t offset_ = 0;
  uint32_t weight_ = 1;
  size_t visits_ = 0;
};

}  // namespace ndtom
