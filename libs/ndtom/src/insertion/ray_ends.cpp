#include "insertion/ray_ends.h"

#include <algorithm>
#include <cstddef>
#include <stdexcept>
#include <string>
#include <unordered_map>

#include "ndtom/map/tile_index.h"
#include "partition/tile_owner_table.h"
#include "support/radix_sort.h"

namespace ndtom {

namespace {

/// Bits needed to write `max_value` (at least 1).
inline int bitsFor(uint64_t max_value) {
  int bits = 1;
  while (bits < 64 && (max_value >> bits) != 0) ++bits;
  return bits;
}

/// The word of used point `i`, whose end is in the cell of dense index `dense`.
inline uint64_t rayEndWord(const ClassifiedPoints& points, const SortedRayEnds& out,
                           uint64_t dense, size_t i) {
  const uint64_t key = dense << 1 | (points.kinds[i] == PointKind::kHit ? 1u : 0u);
  return key << out.point_bits | i;
}

// Keys for ends so far apart that a dense index in their box does not fit a word with the
// point index (thousands of km at fine resolution: glitches): blocks numbered in the order the
// points meet them instead, one thread. Returns the key bits.
int keyByBlockRank(const ClassifiedPoints& points, const TileOwnership* hits_in,
                   SortedRayEnds& out) {
  std::unordered_map<CellIndex, uint64_t, CellIndexHash> rank_of_block;
  CellIndex last_block{};
  uint64_t last_rank = UINT64_MAX;  // consecutive points mostly share a block
  size_t k = 0;
  for (size_t i = 0; i < points.points(); ++i) {
    if (points.kinds[i] == PointKind::kRejected) continue;
    const CellIndex& c = points.end_cells[i];
    if (hits_in && !(points.kinds[i] == PointKind::kHit && hits_in->ownsBlock(blockOf(c))))
      continue;
    const CellIndex b = blockOf(c);
    if (last_rank == UINT64_MAX || b != last_block) {
      last_rank = rank_of_block.try_emplace(b, rank_of_block.size()).first->second;
      last_block = b;
    }
    out.words[k++] = rayEndWord(points, out, last_rank * kBlockCells + uint64_t(offsetInBlock(c)), i);
  }
  out.words.resize(k);
  const int key_bits = bitsFor(2 * kBlockCells * std::max<size_t>(rank_of_block.size(), 1) - 1);
  if (key_bits + out.point_bits > 64)  // over 2^27 points, spread over kilometres
    throw std::invalid_argument("insertScan: " + std::to_string(points.points()) +
                                " points spread over " + std::to_string(rank_of_block.size()) +
                                " blocks are too many for one scan; split it");
  return key_bits;
}

// The words of the points keep(i) accepts and, with `owned_blocks`, that end in a
// block it marks (by dense index), keyed by dense index in the ends' box of blocks (from `lo`,
// nx × ny), in point order: each of classification's chunks keys its points from its usual
// start; where points were left out, the chunks then move down to follow one another.
template <class Keep>
void keyEndsInBox(const ScanContext& scan, const ClassifiedPoints& points, const CellIndex& lo,
                  uint64_t nx, uint64_t ny, Keep&& keep, const uint8_t* owned_blocks,
                  SortedRayEnds& out) {
  std::vector<size_t> kept(points.chunks(), 0);
  scan.pool.run(points.chunks(), [&](size_t t) {
    size_t k = points.used_before[t];
    for (size_t i = points.chunk_starts[t]; i < points.chunk_starts[t + 1]; ++i) {
      if (!keep(i)) continue;
      const CellIndex& c = points.end_cells[i];
      const CellIndex b = blockOf(c);
      const uint64_t block =
          (uint64_t(b.z - lo.z) * ny + uint64_t(b.y - lo.y)) * nx + uint64_t(b.x - lo.x);
      if (owned_blocks && !owned_blocks[block]) continue;
      out.words[k++] = rayEndWord(points, out, block * kBlockCells + uint64_t(offsetInBlock(c)), i);
    }
    kept[t] = k - points.used_before[t];
  });
  size_t k = 0;
  for (size_t t = 0; t < points.chunks(); ++t) {
    const auto first = out.words.begin() + std::ptrdiff_t(points.used_before[t]);
    if (k != points.used_before[t])
      std::copy(first, first + std::ptrdiff_t(kept[t]), out.words.begin() + std::ptrdiff_t(k));
    k += kept[t];
  }
  out.words.resize(k);
}

// Whether each block of the box from `lo` (nx × ny × nz) is in an owned tile, in the keys'
// dense order.
constexpr uint64_t kMaxOwnedBlocksTable = uint64_t(1) << 20;
std::vector<uint8_t> ownedBlocks(const TileOwnerTable::Lookup& owner, int tile_blocks,
                                 const CellIndex& lo, uint64_t nx, uint64_t ny, uint64_t nz) {
  auto tilesOf = [&](int32_t first_block, uint64_t n) {  // per block along an axis
    std::vector<int32_t> t(n);
    for (uint64_t i = 0; i < n; ++i) {
      const int32_t b = first_block + int32_t(i);
      t[i] = tileOfBlock({b, b, b}, tile_blocks).x;
    }
    return t;
  };
  const std::vector<int32_t> tx = tilesOf(lo.x, nx), ty = tilesOf(lo.y, ny), tz = tilesOf(lo.z, nz);
  std::vector<uint8_t> owned(nx * ny * nz);
  size_t k = 0;
  for (uint64_t z = 0; z < nz; ++z)
    for (uint64_t y = 0; y < ny; ++y)
      for (uint64_t x = 0; x < nx; ++x) owned[k++] = owner.ownsTile({tx[x], ty[y], tz[z]});
  return owned;
}

}  // namespace

void sortRayEnds(const ScanContext& scan, const ClassifiedPoints& points,
                 const TileOwnership* hits_in, SortedRayEnds& out) {
  if (points.used == 0) {
    out.words.clear();
    return;
  }
  // Cells keyed by a block-major dense index within the ends' bounding box, so each block's
  // groups are contiguous (threads can own whole blocks); under 2^14 blocks per axis, because
  // rays are at most kMaxRayCells long. The key goes above the point's index in one word.
  out.point_bits = bitsFor(points.points() - 1);
  out.point_mask = (uint64_t(1) << out.point_bits) - 1;
  const CellIndex lo = blockOf(points.ends_lo), hi = blockOf(points.ends_hi);
  const uint64_t nx = uint64_t(hi.x - lo.x) + 1, ny = uint64_t(hi.y - lo.y) + 1;
  const uint64_t nz = uint64_t(hi.z - lo.z) + 1;
  int key_bits = bitsFor(2 * kBlockCells * nx * ny * nz - 1);
  out.words.resize(points.used);  // every word is written below: zeroes only what it grows
  if (key_bits + out.point_bits <= 64) {
    if (hits_in) {  // the hits in its tiles
      // Neighbouring points often lie in different tiles: a table, not a hash per point.
      const TileOwnerTable tiles(*hits_in, points.ends_lo, points.ends_hi);
      const TileOwnerTable::Lookup owner = tiles.lookup();  // in registers, not rebuilt per point
      auto isHit = [&](size_t i) { return points.kinds[i] == PointKind::kHit; };
      if (nx * ny * nz <= kMaxOwnedBlocksTable) {  // the box's blocks' owners: one load a hit
        const std::vector<uint8_t> owned = ownedBlocks(owner, hits_in->tile_blocks, lo, nx, ny, nz);
        keyEndsInBox(scan, points, lo, nx, ny, isHit, owned.data(), out);
      } else {
        keyEndsInBox(scan, points, lo, nx, ny, [&](size_t i) {
          return isHit(i) && owner.ownsCell(points.end_cells[i]);
        }, nullptr, out);
      }
    } else {  // every used point
      keyEndsInBox(scan, points, lo, nx, ny,
                   [&](size_t i) { return points.kinds[i] != PointKind::kRejected; }, nullptr,
                   out);
    }
  } else {
    key_bits = keyByBlockRank(points, hits_in, out);
  }
  radixSortByBits(out.words, out.sort_buffer, out.point_bits, key_bits, scan.pool,
                  scan.threadsFor(out.words.size(), kMinPointsPerThread));
}

}  // namespace ndtom
