// Scan-local free-ray counters N_e (Eq. 12), in blocks shaped like the map's, behind a small
// open-addressing table. Block memory is reused across scans. The hot loop (CountingVisitor)
// caches the current block, so a visit is a compare and an increment.
#pragma once

#include <algorithm>
#include <array>
#include <atomic>
#include <cstdint>
#include <cstring>
#include <memory>
#include <vector>

#include "ndtom/map/block_grid.h"

namespace ndtom {

/// Counters are read in groups of 8 (32 bytes), most of which are zero.
inline constexpr int kCountGroup = 8;

struct CountBlock {
  std::array<uint32_t, kBlockCells> count;
  CellIndex index;  ///< block coordinates, while the block is in use this scan
  /// Face neighbours in use this scan, [2 * axis + (step > 0)]; null until first followed.
  std::array<CountBlock*, 6> neighbour;

  void zero() { std::memset(count.data(), 0, sizeof(count)); }
};

/// Thrown by ScanCounts when the scan's block limit is reached (see setBlockLimit).
struct BlockLimitReached {};

class alignas(64) ScanCounts {  // one per thread: no shared cache line
 public:
  /// Memory one block in use takes: the counters, their owner, the index and table slots.
  static constexpr size_t kBytesPerBlock =
      sizeof(CountBlock) + sizeof(std::unique_ptr<CountBlock>) + sizeof(CellIndex) + 4 * 16;

  ScanCounts() { rehash(1024); }

  /// Blocks the scan's tables may still add, shared by them (the memory budget); each new
  /// block in use takes one, and with none left blockAt() throws BlockLimitReached. Checked
  /// only when a block is added, never per visit. nullptr: no limit.
  void setBlockLimit(std::atomic<int64_t>* left) { left_ = left; }

  /// Frees every block (after a scan that failed, e.g. over the memory budget).
  void releaseMemory() {
    std::vector<std::unique_ptr<CountBlock>>().swap(blocks_);
    std::vector<CellIndex>().swap(used_);
    std::vector<Entry>().swap(table_);
    rehash(1024);
  }

  /// The counters of a block, created (zeroed) on first use this scan.
  CountBlock& blockAt(const CellIndex& block) { return blockFor(block); }

  /// Counters of a block, or nullptr if no ray crossed it.
  CountBlock* findBlock(const CellIndex& block) {
    const int64_t slot = findSlot(block);
    return slot < 0 ? nullptr : blocks_[table_[size_t(slot)].block].get();
  }

  /// Position of a block in blockIndex() order, or -1 if no ray crossed it.
  int64_t indexOf(const CellIndex& block) const {
    const int64_t slot = findSlot(block);
    return slot < 0 ? -1 : int64_t(table_[size_t(slot)].block);
  }

  size_t numBlocks() const { return used_.size(); }
  const CellIndex& blockIndex(size_t i) const { return used_[i]; }
  CountBlock& block(size_t i) { return *blocks_[i]; }

  /// The block across face `face` (see CountBlock::neighbour) of `from`, a block of this table.
  CountBlock& neighbour(CountBlock& from, int face) {
    CountBlock*& link = from.neighbour[size_t(face)];
    if (!link) {
      CellIndex b = from.index;
      b[face / 2] += face % 2 ? 1 : -1;
      link = &blockFor(b);
      link->neighbour[size_t(face ^ 1)] = &from;
    }
    return *link;
  }

  /// Forgets all blocks; their memory is kept for the next scan. Callers zero the blocks
  /// they read (while they are in cache) with zeroBlock(), or clear() does it.
  void clear() { clear(used_.size()); }
  /// The same, when only the first `written` blocks may hold non-zero counters.
  void clear(size_t written) {
    for (size_t i = 0; i < std::min(written, used_.size()); ++i) zeroBlock(i);
    reset();
  }
  void zeroBlock(size_t i) { blocks_[i]->zero(); }
  /// Forgets (zeroed, for reuse) the blocks whose index `keep` refuses; the others keep their
  /// counters, in their order. Neighbour links are not valid afterwards (until the next scan).
  template <class Keep>
  void keepBlocksWhere(Keep&& keep) {
    size_t kept = 0;
    for (size_t i = 0; i < used_.size(); ++i) {
      if (!keep(used_[i])) {
        blocks_[i]->zero();
        continue;
      }
      std::swap(blocks_[kept], blocks_[i]);
      used_[kept++] = used_[i];
    }
    used_.resize(kept);
    rehash(table_.size());
  }
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
      if (e.key == b) return *blocks_[e.block];
    }
    if (left_ && left_->fetch_sub(1, std::memory_order_relaxed) <= 0) throw BlockLimitReached{};
    // New block this scan: reuse zeroed memory from earlier scans when there is some.
    const uint32_t index = uint32_t(used_.size());
    if (index == blocks_.size()) {
      blocks_.push_back(std::make_unique<CountBlock>());
      blocks_.back()->zero();
    }
    used_.push_back(b);
    table_[slot] = {b, index};
    if (2 * used_.size() > table_.size()) {  // keep the load factor under 1/2
      rehash(table_.size() * 2);
    }
    CountBlock& block = *blocks_[index];
    block.index = b;
    block.neighbour.fill(nullptr);
    return block;
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
  /// blocks_[i] belongs to used_[i]; the rest are spare. Owned one by one, so that walkers'
  /// pointers and neighbour links survive the table growing.
  std::vector<std::unique_ptr<CountBlock>> blocks_;
  std::vector<CellIndex> used_;
  std::atomic<int64_t>* left_ = nullptr;
};

/// The ray walker of the free-space pass (see walkRay): adds `weight` to every cell visited.
/// It follows the walk incrementally as a block and an offset in it, so a visit is an
/// increment and leaving a block follows a neighbour link. The state is a few scalars and no
/// member's address leaves the walker, so the compiler can keep it in registers.
/// kUnitWeight: every ray weighs 1 (one ray per point), known at compile time, so the weight
/// takes no register (with it, the walk spilled it to the stack and loaded it per visit).
template <bool kUnitWeight>
class BasicCountingWalker {
 public:
  explicit BasicCountingWalker(ScanCounts& counts) : counts_(&counts) {}
  void setWeight(uint32_t w) {
    static_assert(!kUnitWeight, "a unit-weight walker has no weight to set");
    weight_ = w;
  }
  size_t visits() const { return visits_; }

  void start(const CellIndex& c) {
    const CellIndex b = blockOf(c);
    // A scan's rays all start at the sensor, and the last one ended elsewhere: the block of
    // the last start saves a table lookup per ray.
    if (!block_ || b != block_->index)
      block_ = start_block_ && b == start_block_->index ? start_block_ : lookUp(counts_, b.x, b.y, b.z);
    start_block_ = block_;
    offset_ = offsetInBlock(c);
  }

  /// start() for a walk resumed mid-ray (a distributed build's process): the rays' start
  /// block stays cached for the next ray.
  void resume(const CellIndex& c) {
    const CellIndex b = blockOf(c);
    if (!block_ || b != block_->index) block_ = lookUp(counts_, b.x, b.y, b.z);
    offset_ = offsetInBlock(c);
  }

  template <int Axis>
  void move(int32_t step) {
    constexpr int32_t kMask = (kBlockEdge - 1) << (Axis * kBlockLog2);  // x fastest
    const int32_t moved = offset_ + step * (1 << (Axis * kBlockLog2));
    // The carry or borrow stayed in this axis (7 steps in 8).
    if (__builtin_expect(((moved ^ offset_) & ~kMask) == 0, 1)) {
      offset_ = moved;
      return;
    }
    // Left the block: wrap to the other side of the next one.
    offset_ = (offset_ & ~kMask) | (moved & kMask);
    block_ = follow(counts_, block_, 2 * Axis + (step > 0));
  }

  bool visit() {
    block_->count[size_t(offset_)] += kUnitWeight ? 1 : weight_;
    ++visits_;
    return true;
  }

 private:
  // Out of line and by value: a reference to a member would pin the walker in memory.
  [[gnu::noinline]] static CountBlock* lookUp(ScanCounts* counts, int32_t x, int32_t y, int32_t z) {
    return &counts->blockAt(CellIndex{x, y, z});
  }
  static CountBlock* follow(ScanCounts* counts, CountBlock* from, int face) {
    CountBlock* next = from->neighbour[size_t(face)];
    return next ? next : linkNeighbour(counts, from, face);
  }
  [[gnu::noinline]] static CountBlock* linkNeighbour(ScanCounts* counts, CountBlock* from,
                                                     int face) {
    return &counts->neighbour(*from, face);
  }

  ScanCounts* counts_;
  CountBlock* block_ = nullptr;
  CountBlock* start_block_ = nullptr;  ///< where the last ray started
  int32_t offset_ = 0;  ///< of the current cell in its block
  uint32_t weight_ = 1;
  size_t visits_ = 0;
};

using CountingWalker = BasicCountingWalker<false>;
using UnitCountingWalker = BasicCountingWalker<true>;

}  // namespace ndtom
