#include "ndtom/registration/map_pyramid.h"

#include <algorithm>
#include <atomic>
#include <iterator>
#include <stdexcept>
#include <string>

#include "map/map_internals.h"
#include "ndtom/map/memory_budget.h"
#include "registration/coarse_cells.h"
#include "support/parallel.h"

namespace ndtom {

using registration::CoarseCells;

struct MapPyramid::Work {
  size_t threads = 1;
  WorkerPool pool;
};

namespace {

void checkFactors(const std::vector<int>& factors) {
  if (factors.empty()) throw std::invalid_argument("level factors: none given");
  for (size_t i = 0; i < factors.size(); ++i) {
    if (factors[i] < 1 || factors[i] > 1024)
      throw std::invalid_argument("level factors: " + std::to_string(factors[i]) +
                                  " is not in [1, 1024]");
    if (i > 0 && factors[i] >= factors[i - 1])
      throw std::invalid_argument("level factors: must be given coarse to fine, decreasing");
  }
}

std::string levelNames(const std::vector<int>& factors) {
  std::string names;
  for (const int f : factors) names += (names.empty() ? "x" : " x") + std::to_string(f);
  return names;
}

// f(level, i, scratch) for items i < sizes[level] of every level, each on its own: threads
// take runs of `per_take` as they go, each with its own default-made Scratch. Returns the
// sum of what f returns.
template <class Scratch, class F>
size_t forEachLevelItem(WorkerPool& pool, size_t threads, const std::vector<size_t>& sizes,
                        size_t per_take, F&& f) {
  std::vector<size_t> starts{0};
  for (const size_t n : sizes) starts.push_back(starts.back() + n);
  const size_t total = starts.back();
  std::atomic<size_t> next{0}, sum{0};
  pool.run(threadsFor(total, per_take, threads), [&](size_t) {
    Scratch scratch{};
    size_t sum_here = 0;
    for (size_t begin; (begin = next.fetch_add(per_take)) < total;)
      for (size_t k = begin; k < std::min(total, begin + per_take); ++k) {
        const size_t l =
            size_t(std::upper_bound(starts.begin(), starts.end(), k) - starts.begin()) - 1;
        sum_here += f(l, k - starts[l], scratch);
      }
    sum += sum_here;
  });
  return sum.load();
}

// f(level) for each of `levels` levels, one level per thread: a level's lookup is one object.
template <class F>
void forEachLevel(WorkerPool& pool, size_t threads, size_t levels, F&& f) {
  threads = std::min(threads, levels);
  pool.run(threads, [&](size_t t) {
    for (size_t l = t; l < levels; l += threads) f(l);
  });
}

}  // namespace

MapPyramid::MapPyramid(const NdtMap& map, const std::vector<int>& factors, int threads,
                       BlockFilter members)
    : factors_(factors),
      revision_(map.revision()),
      members_(std::move(members)),
      work_(std::make_unique<Work>()) {
  checkFactors(factors);
  work_->threads = size_t(std::max(threads, 1));
  const Threads all{work_->pool, work_->threads};
  // Coarse levels from the cells with statistics only: the coarse map's free cells, most of
  // its cells, are never needed here.
  const std::vector<BlockCells> fine = CoarseCells(map, 1, members_).statsCells();
  std::vector<std::vector<BlockCells>> blocks;
  for (const int factor : factors_)
    blocks.push_back(CoarseCells(map, factor, members_).blocksOver(fine, false, all));
  build(map, blocks);
}

void MapPyramid::build(const NdtMap& map, const std::vector<std::vector<BlockCells>>& blocks) {
  // Every (level, coarse block) on its own, its Gaussians made and kept by the thread that
  // takes it.
  std::vector<CoarseCells> coarse;
  std::vector<std::vector<GaussianBlock>> made(factors_.size());
  std::vector<size_t> sizes;
  for (size_t l = 0; l < factors_.size(); ++l) {
    coarse.emplace_back(map, factors_[l], members_);
    made[l].resize(blocks[l].size());
    sizes.push_back(blocks[l].size());
  }
  constexpr size_t kBlocksPerTake = 8;
  const size_t found = forEachLevelItem<std::vector<PreparedGaussian>>(
      work_->pool, work_->threads, sizes, kBlocksPerTake,
      [&](size_t l, size_t i, std::vector<PreparedGaussian>& gaussians) {
        const BlockCells& cells = blocks[l][i];
        GaussianBlock& out = made[l][i];
        out.block = cells.block;
        gaussians.clear();
        for (size_t w = 0; w < cells.cells.size(); ++w)
          for (uint64_t bits = cells.cells[w]; bits != 0; bits &= bits - 1) {
            const int offset = int(w * 64) + __builtin_ctzll(bits);
            std::optional<PreparedGaussian> g = coarse[l].gaussian(cellInBlock(cells.block, offset));
            if (!g) continue;
            gaussians.push_back(std::move(*g));
            out.cells[w] |= uint64_t(1) << (offset & 63);
          }
        out.gaussians.reserve(gaussians.size());  // exactly: memoryBytes() counts capacity
        std::move(gaussians.begin(), gaussians.end(), std::back_inserter(out.gaussians));
        return gaussians.size();
      });
  checkBudget(map, found, /*beside_levels=*/false);
  levels_.resize(factors_.size());
  forEachLevel(work_->pool, work_->threads, factors_.size(), [&](size_t l) {
    const LookupOptions options{/*occupied_only=*/true, /*nearest_means=*/false};
    const GridGeometry geometry(map.options().resolution * factors_[l]);
    levels_[l] = std::make_unique<GaussianLookup>(geometry, std::move(made[l]), options);
  });
}

MapPyramid::~MapPyramid() = default;

size_t MapPyramid::memoryBytes() const {
  size_t bytes = 0;
  for (const auto& level : levels_) bytes += level->memoryBytes();
  return bytes;
}

bool MapPyramid::follow(const NdtMap& map) {
  if (map.revision() == revision_) return true;
  const StatsChanges& changes = map.lastStatsChanges();
  if (changes.from == 0 || changes.from != revision_ || changes.to != map.revision()) return false;
  const Threads all{work_->pool, work_->threads};
  std::vector<std::vector<CellIndex>> cells(factors_.size());
  for (size_t l = 0; l < factors_.size(); ++l)
    cells[l] = CoarseCells(map, factors_[l], members_).cellsOver(changes.blocks, true, all);
  redo(map, cells, members_);
  revision_ = map.revision();
  return true;
}

void MapPyramid::setMembers(const NdtMap& map, BlockFilter members) {
  if (map.revision() != revision_)
    throw std::logic_error("MapPyramid::setMembers: the pyramid is not at the map's revision");
  const auto admits = [](const BlockFilter& filter, const CellIndex& block) {
    return !filter || filter(block);
  };
  std::vector<BlockCells> moved;  // blocks that join or leave, all their cells
  for (const auto& [key, block] : MapInternals::grid(map).blocks())
    if (!block->stats.empty() && admits(members_, key) != admits(members, key))
      moved.push_back({key, block->has_stats});
  const Threads all{work_->pool, work_->threads};
  std::vector<std::vector<CellIndex>> cells(factors_.size());
  for (size_t l = 0; l < factors_.size(); ++l)
    cells[l] = CoarseCells(map, factors_[l], members).cellsOver(moved, false, all);
  redo(map, cells, members);
  members_ = std::move(members);
}

void MapPyramid::checkBudget(const NdtMap& map, size_t gaussians, bool beside_levels) const {
  // The levels share what the map's memory budget leaves: a sparse map (a Gaussian a
  // block) has levels as large as itself. Gaussians redone are held beside the levels
  // until they replace them, so they count whole.
  const uint64_t budget = map.options().scan.memory_budget;
  const uint64_t need = map.memoryBytes() + (beside_levels ? memoryBytes() : 0) +
                        gaussians * GaussianLookup::maxBytesPerGaussian();
  if (need > budget)
    throw MemoryBudgetError("the registration pyramid (levels " + levelNames(factors_) + ", " +
                                std::to_string(gaussians) + " Gaussians, beside the map)",
                            need, budget);
}

void MapPyramid::redo(const NdtMap& map, const std::vector<std::vector<CellIndex>>& cells,
                      const BlockFilter& members) {
  size_t gaussians = 0;
  std::vector<std::vector<CellChange>> changes = redoCells(map, cells, members, gaussians);
  checkBudget(map, gaussians, /*beside_levels=*/true);
  forEachLevel(work_->pool, work_->threads, factors_.size(),
               [&](size_t l) { levels_[l]->update(std::move(changes[l])); });
}

std::vector<std::vector<CellChange>> MapPyramid::redoCells(
    const NdtMap& map, const std::vector<std::vector<CellIndex>>& cells, const BlockFilter& members,
    size_t& gaussians) {
  // Every (level, cell) on its own.
  std::vector<CoarseCells> coarse;
  std::vector<std::vector<CellChange>> changes(factors_.size());
  std::vector<size_t> sizes;
  for (size_t l = 0; l < factors_.size(); ++l) {
    coarse.emplace_back(map, factors_[l], members);
    changes[l].resize(cells[l].size());
    sizes.push_back(cells[l].size());
  }
  constexpr size_t kCellsPerTake = 256;
  gaussians = forEachLevelItem<int>(work_->pool, work_->threads, sizes, kCellsPerTake,
                                    [&](size_t l, size_t i, int&) -> size_t {
                                      CellChange& change = changes[l][i];
                                      change.cell = cells[l][i];
                                      change.gaussian = coarse[l].gaussian(change.cell);
                                      return change.gaussian.has_value();
                                    });
  return changes;
}

}  // namespace ndtom
