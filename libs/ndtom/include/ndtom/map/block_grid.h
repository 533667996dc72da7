// A sparse, unbounded grid of fixed-size blocks of cells behind a hash map (as in Bonxai).
// Memory grows with the blocks touched, never with a bounding box; cells of one block sit
// together in memory, so a ray's consecutive cells usually hit the same block.
#pragma once

#include <cstdint>
#include <memory>
#include <unordered_map>

#include "ndtom/map/cell_index.h"

namespace ndtom {

inline constexpr int kBlockLog2 = 3;
inline constexpr int kBlockEdge = 1 << kBlockLog2;
inline constexpr int kBlockCells = kBlockEdge * kBlockEdge * kBlockEdge;

/// Block coordinates of a cell. GCC and Clang shift signed values arithmetically (C++20
/// guarantees it), so this is floor division for negative indices too.
inline CellIndex blockOf(const CellIndex& c) {
  return {c.x >> kBlockLog2, c.y >> kBlockLog2, c.z >> kBlockLog2};
}

/// Offset of a cell inside its block, x fastest.
inline int offsetInBlock(const CellIndex& c) {
  constexpr int32_t mask = kBlockEdge - 1;
  return ((c.z & mask) << (2 * kBlockLog2)) | ((c.y & mask) << kBlockLog2) | (c.x & mask);
}

/// The cell at `offset` (offsetInBlock()) in `block`.
inline CellIndex cellInBlock(const CellIndex& block, int offset) {
  constexpr int mask = kBlockEdge - 1;
  return {block.x * kBlockEdge + (offset & mask),
          block.y * kBlockEdge + ((offset >> kBlockLog2) & mask),
          block.z * kBlockEdge + (offset >> (2 * kBlockLog2))};
}

/// Cells block by block (ascending block coordinates), then by offset in a block: the order
/// in which a block's cells sit together (GaussianLookup's blocks, a pyramid's updates).
inline bool inBlockOrder(const CellIndex& a, const CellIndex& b) {
  const CellIndex block_a = blockOf(a), block_b = blockOf(b);
  if (block_a != block_b) return block_a < block_b;
  return offsetInBlock(a) < offsetInBlock(b);
}

/// Blocks of type Block (default-constructible) indexed by block coordinates.
template <class Block>
class BlockGrid {
 public:
  using Map = std::unordered_map<CellIndex, std::unique_ptr<Block>, CellIndexHash>;

  BlockGrid() = default;
  BlockGrid(BlockGrid&&) noexcept = default;
  BlockGrid& operator=(BlockGrid&&) noexcept = default;
  BlockGrid(const BlockGrid& other) { *this = other; }
  BlockGrid& operator=(const BlockGrid& other) {
    if (this == &other) return *this;
    Map copy;
    copy.reserve(other.blocks_.size());
    for (const auto& [key, block] : other.blocks_)
      copy.emplace(key, std::make_unique<Block>(*block));
    blocks_.swap(copy);
    return *this;
  }

  /// Never allocates: nullptr when the block does not exist.
  const Block* find(const CellIndex& block) const {
    const auto it = blocks_.find(block);
    return it == blocks_.end() ? nullptr : it->second.get();
  }
  Block* find(const CellIndex& block) {
    const auto it = blocks_.find(block);
    return it == blocks_.end() ? nullptr : it->second.get();
  }

  /// The block, created default-constructed if missing. `created` tells which happened.
  Block& getOrCreate(const CellIndex& block, bool* created = nullptr) {
    auto [it, inserted] = blocks_.try_emplace(block);
    if (inserted) {
      try {
        it->second = std::make_unique<Block>();
      } catch (...) {
        blocks_.erase(it);
        throw;
      }
    }
    if (created) *created = inserted;
    return *it->second;
  }

  void erase(const CellIndex& block) { blocks_.erase(block); }
  void clear() { blocks_.clear(); }
  size_t size() const { return blocks_.size(); }
  void reserve(size_t n) { blocks_.reserve(n); }

  const Map& blocks() const { return blocks_; }
  Map& blocks() { return blocks_; }

  /// What one more block adds to memoryBytes(): the block, its node and a bucket.
  static constexpr size_t kBytesPerBlock = sizeof(Block) + sizeof(typename Map::value_type) +
                                           sizeof(void*) + sizeof(size_t) + sizeof(void*);

  /// Approximate heap bytes: blocks, their owning pointers and the hash table's nodes/buckets.
  size_t memoryBytes() const {
    constexpr size_t kNodeOverhead = sizeof(void*) + sizeof(size_t);  // next pointer + cached hash
    return blocks_.size() * (sizeof(Block) + sizeof(typename Map::value_type) + kNodeOverhead) +
           blocks_.bucket_count() * sizeof(void*);
  }

 private:
  Map blocks_;
};

}  // namespace ndtom
