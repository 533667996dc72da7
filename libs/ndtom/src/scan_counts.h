// Scan-local free-ray counters N_e (Eq. 12), in blocks shaped like the map's, behind a small
// open-addressing table. Block memory is reused across scans. The hot loop (CountingVisitor)
// caches the current block, so a visit is a compare and an increment.
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstring>
#include <vector>

#include "ndtom/block_grid.h"

namespace ndtom {

/// Counters are read in groups of 8 (32 bytes), most of which are zero.
inline constexpr int kCountGroup = 8;

struct CountBlock {
  std::array<uint32_t, kBlockCells> count;

  void zero() { std::memset(count.data(), 0, sizeof(count)); }
};

class ScanCounts {
 public:
  ScanCounts() { rehash(1024); }

  /// The counters of a block, created (zeroed) on first use this scan.
  CountBlock& blockAt(const CellIndex& block) { return blockFor(block); }

  /// Counter of a cell, or nullptr if no ray crossed its block.
  uint32_t* find(const CellIndex& c) {
    const int64_t slot = findSlot(blockOf(c));
    return slot < 0 ? nullptr : &blocks_[table_[size_t(slot)].block].count[offsetInBlock(c)];
  }

  /// Counters of a block, or nullptr if no ray crossed it.
  CountBlock* findBlock(const CellIndex& block) {
    const int64_t slot = findSlot(block);
    return slot < 0 ? nullptr : &blocks_[table_[size_t(slot)].block];
  }

  /// Position of a block in blockIndex() order, or -1 if no ray crossed it.
  int64_t indexOf(const CellIndex& block) const {
    const int64_t slot = findSlot(block);
    return slot < 0 ? -1 : int64_t(table_[size_t(slot)].block);
  }

  size_t numBlocks() const { return used_.size(); }
  const CellIndex& blockIndex(size_t i) const { return used_[i]; }
  CountBlock& block(size_t i) { return blocks_[i]; }

  /// Forgets all blocks; their memory is kept for the next scan. Callers zero the blocks
  /// they read (while they are in cache) with zeroBlock(), or clear() does it.
  void clear() {
    for (size_t i = 0; i < used_.size(); ++i) zeroBlock(i);
    reset();
  }
  void zeroBlock(size_t i) { blocks_[i].zero(); }
  /// After every block was zeroed by zeroBlock().
  void reset() {
    // Erasing entry by entry would break linear-probe chains; the table is small (16 bytes
    // per slot, under 4 slots per 2 KiB block), so wipe it whole.
    std::fill(table_.begin(), table_.end(), Entry{});
    used_.clear();
  }

 private:
  static constexpr uint32_t kEmpty = UINT32_MAX;
  struct Entry {
    CellIndex key;
    uint32_t block = kEmpty;  ///< index into blocks_ and used_
  };

  CountBlock& blockFor(const CellIndex& b) {
    size_t slot = CellIndexHash{}(b)&mask_;
    for (;; slot = (slot + 1) & mask_) {
      Entry& e = table_[slot];
      if (e.block == kEmpty) break;
      if (e.key == b) return blocks_[e.block];
    }
    // New block this scan: reuse zeroed memory from earlier scans when there is some.
    const uint32_t index = uint32_t(used_.size());
    if (index == blocks_.size()) {
      blocks_.emplace_back();
      blocks_.back().zero();
    }
    used_.push_back(b);
    table_[slot] = {b, index};
    if (2 * used_.size() > table_.size()) {  // keep the load factor under 1/2
      rehash(table_.size() * 2);
    }
    return blocks_[index];
  }

  int64_t findSlot(const CellIndex& b) const {
    for (size_t slot = CellIndexHash{}(b)&mask_;; slot = (slot + 1) & mask_) {
      const Entry& e = table_[slot];
      if (e.block == kEmpty) return -1;
      if (e.key == b) return int64_t(slot);
    }
  }

  void rehash(size_t capacity) {
    table_.assign(capacity, Entry{});
    mask_ = capacity - 1;
    for (uint32_t i = 0; i < used_.size(); ++i) {
      size_t slot = CellIndexHash{}(used_[i]) & mask_;
      while (table_[slot].block != kEmpty) slot = (slot + 1) & mask_;
      table_[slot] = {used_[i], i};
    }
  }

  std::vector<Entry> table_;
  size_t mask_ = 0;
  std::vector<CountBlock> blocks_;  ///< blocks_[i] belongs to used_[i]; the rest are spare
  std::vector<CellIndex> used_;
};

/// The ray walker of the free-space pass (see walkRay): adds `weight` to every cell visited.
/// It follows the walk incrementally, block and in-block coordinates, so a visit is an
/// increment and a block is looked up only when the ray leaves it.
class CountingWalker {
 public:
  explicit CountingWalker(ScanCounts& counts) : counts_(&counts) {}
  void setWeight(uint32_t w) { weight_ = w; }
  size_t visits() const { return visits_; }

  void start(const CellIndex& c) {
    const CellIndex b = blockOf(c);
    if (!block_counts_ || b != block_) {  // rays share their origin's block
      block_ = b;
      block_counts_ = &counts_->blockAt(b);
    }
    constexpr int32_t mask = kBlockEdge - 1;
    local_[0] = c.x & mask;
    local_[1] = c.y & mask;
    local_[2] = c.z & mask;
    offset_ = offsetInBlock(c);
  }

  template <int Axis>
  void move(int32_t step) {
    constexpr int kShift = Axis * kBlockLog2;  // x fastest, as offsetInBlock
    local_[Axis] += step;
    if (uint32_t(local_[Axis]) < uint32_t(kBlockEdge)) {
      offset_ += step * (1 << kShift);
      return;
    }
    // Left the block: wrap to the other side of the next one.
    local_[Axis] &= kBlockEdge - 1;
    offset_ = (local_[2] << (2 * kBlockLog2)) | (local_[1] << kBlockLog2) | local_[0];
    block_[Axis] += step;
    block_counts_ = &counts_->blockAt(block_);
  }

  bool visit() {
    block_counts_->count[offset_] += weight_;
    ++visits_;
    return true;
  }

 private:
  ScanCounts* counts_;
  CountBlock* block_counts_ = nullptr;
  CellIndex block_;
  int32_t local_[3] = {0, 0, 0};
  int32_t offset_ = 0;  ///< of the current cell in its block
  uint32_t weight_ = 1;
  size_t visits_ = 0;
};

}  // namespace ndtom
