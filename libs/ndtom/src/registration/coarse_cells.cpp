#include "registration/coarse_cells.h"

#include <algorithm>

#include "map/map_internals.h"
#include "ndtom/map/map_queries.h"

namespace ndtom::registration {

static_assert(kBlockEdge * kBlockEdge == 64, "a word of a block's masks is one z layer");

CoarseCells::CoarseCells(const NdtMap& map, int factor, const BlockFilter& members)
    : map_(map), factor_(factor), members_(members), geometry_(map.options().resolution * factor) {}

std::optional<PreparedGaussian> CoarseCells::gaussian(const CellIndex& coarse_cell) const {
  if (factor_ == 1) {
    if (!member(blockOf(coarse_cell))) return std::nullopt;
    const std::optional<CellView> fine = map_.cell(coarse_cell);
    if (!fine || !isOccupiedGaussian(map_, *fine)) return std::nullopt;
    return prepared(map_.gaussianOf(*fine, Covariance::Exact), map_.options().regularization);
  }
  const double r = map_.options().resolution;
  const double half_coarse = 0.5 * r * factor_;
  const CellIndex lo{coarse_cell.x * factor_, coarse_cell.y * factor_, coarse_cell.z * factor_};
  const CellIndex hi{lo.x + factor_ - 1, lo.y + factor_ - 1, lo.z + factor_ - 1};
  const CellIndex block_lo = blockOf(lo), block_hi = blockOf(hi);
  const BlockGrid<MapBlock>& grid = MapInternals::grid(map_);
  CellStats merged;
  // Blocks in ascending CellIndex order (x, then y, then z), cells in offset order.
  for (int32_t bx = block_lo.x; bx <= block_hi.x; ++bx)
    for (int32_t by = block_lo.y; by <= block_hi.y; ++by)
      for (int32_t bz = block_lo.z; bz <= block_hi.z; ++bz) {
        const CellIndex key{bx, by, bz};
        const MapBlock* block = grid.find(key);
        if (!block || block->stats.empty() || !member(key)) continue;
        // The part of the coarse cell in this block: x and y make a mask within each z
        // layer (a word of has_stats holds one layer of 8×8 cells).
        const CellIndex first = cellInBlock(key, 0);
        const int x0 = std::max(lo.x - first.x, 0), x1 = std::min(hi.x - first.x, kBlockEdge - 1);
        const int y0 = std::max(lo.y - first.y, 0), y1 = std::min(hi.y - first.y, kBlockEdge - 1);
        const int z0 = std::max(lo.z - first.z, 0), z1 = std::min(hi.z - first.z, kBlockEdge - 1);
        const uint64_t row = ((uint64_t(2) << (x1 - x0)) - 1) << x0;
        uint64_t layer = 0;
        for (int y = y0; y <= y1; ++y) layer |= row << (kBlockEdge * y);
        size_t before = 0;  // statistics in the layers below z
        for (int z = 0; z < z0; ++z)
          before += size_t(__builtin_popcountll(block->has_stats[size_t(z)]));
        for (int z = z0; z <= z1; ++z) {
          const uint64_t has = block->has_stats[size_t(z)];
          for (uint64_t bits = has & layer; bits != 0; bits &= bits - 1) {
            const int bit = __builtin_ctzll(bits);
            const size_t pos =
                before + size_t(__builtin_popcountll(has & ((uint64_t(1) << bit) - 1)));
            const CellIndex fine = cellInBlock(key, z * 64 + bit);
            // Fine centre minus coarse centre, from small integers: exact for dyadic
            // resolutions.
            Eigen::Vector3d offset;
            for (int a = 0; a < 3; ++a)
              offset[a] = r * (double(fine[a] - lo[a]) + 0.5 - 0.5 * factor_);
            merged.merge(block->stats[pos].shifted(-offset));
            merged.clampMean(half_coarse);
          }
          before += size_t(__builtin_popcountll(has));
        }
      }
  if (!merged.hasGaussian()) return std::nullopt;
  Gaussian g;
  g.cell = coarse_cell;
  g.n = merged.n;
  g.mean = geometry_.cellCenter(coarse_cell) + merged.relative_mean;
  g.covariance = merged.covariance();
  return prepared(g, map_.options().regularization);
}

namespace {

// The bits, in their coarse block, of the coarse cells over the fine cells `fine`.
void addCoarseBits(const BlockCells& fine, int factor, std::array<uint64_t, kBlockCells / 64>& bits) {
  if (factor == 1) {
    for (size_t w = 0; w < bits.size(); ++w) bits[w] |= fine.cells[w];
    return;
  }
  for (size_t w = 0; w < fine.cells.size(); ++w)
    for (uint64_t word = fine.cells[w]; word != 0; word &= word - 1) {
      const CellIndex coarse = cellwiseFloorDiv(
          cellInBlock(fine.block, int(w * 64) + __builtin_ctzll(word)), factor);
      const int offset = offsetInBlock(coarse);  // in the fine block's coarse block
      bits[size_t(offset) >> 6] |= uint64_t(1) << (offset & 63);
    }
}

}  // namespace

std::vector<BlockCells> CoarseCells::blocksOver(const std::vector<BlockCells>& fine,
                                                bool members_only, const Threads& threads) const {
  // A fine block's cells all fall in one coarse block, floor(block / factor): a coarse cell's
  // block is floor(fine cell / (8·factor)), and a fine block spans 8 fine cells.
  std::vector<std::pair<CellIndex, uint32_t>> by_coarse;  // coarse block, index into `fine`
  by_coarse.reserve(fine.size());
  const auto any = [](const BlockCells& b) {
    return std::any_of(b.cells.begin(), b.cells.end(), [](uint64_t w) { return w != 0; });
  };
  for (size_t i = 0; i < fine.size(); ++i)
    if (any(fine[i]) && (!members_only || member(fine[i].block)))
      by_coarse.emplace_back(cellwiseFloorDiv(fine[i].block, factor_), uint32_t(i));
  // Ties in any order: the bits are or-ed.
  std::sort(by_coarse.begin(), by_coarse.end(),
            [](const auto& a, const auto& b) { return a.first < b.first; });
  std::vector<size_t> starts;
  for (size_t k = 0; k < by_coarse.size(); ++k)
    if (k == 0 || by_coarse[k].first != by_coarse[k - 1].first) starts.push_back(k);
  starts.push_back(by_coarse.size());
  std::vector<BlockCells> coarse(starts.size() - 1);
  constexpr size_t kMinBlocksPerThread = 256;
  const size_t parts = threads.forItems(coarse.size(), kMinBlocksPerThread);
  threads.pool.run(parts, [&](size_t t) {
    const auto [begin, end] = partRange(coarse.size(), parts, t);
    for (size_t g = begin; g < end; ++g) {
      coarse[g].block = by_coarse[starts[g]].first;
      for (size_t k = starts[g]; k < starts[g + 1]; ++k)
        addCoarseBits(fine[by_coarse[k].second], factor_, coarse[g].cells);
    }
  });
  return coarse;
}

std::vector<CellIndex> CoarseCells::cellsOver(const std::vector<BlockCells>& fine,
                                              bool members_only, const Threads& threads) const {
  std::vector<CellIndex> out;
  for (const BlockCells& b : blocksOver(fine, members_only, threads))
    for (size_t w = 0; w < b.cells.size(); ++w)
      for (uint64_t bits = b.cells[w]; bits != 0; bits &= bits - 1)
        out.push_back(cellInBlock(b.block, int(w * 64) + __builtin_ctzll(bits)));
  return out;
}

std::vector<BlockCells> CoarseCells::statsCells() const {
  std::vector<BlockCells> fine;
  for (const auto& [key, block] : MapInternals::grid(map_).blocks())
    if (!block->stats.empty() && member(key)) fine.push_back({key, block->has_stats});
  return fine;
}

}  // namespace ndtom::registration
