#include "ndtom/map/ndt_map.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <stdexcept>

#include "map/map_block.h"
#include "ndtom/map/cell_rules.h"
#include "ndtom/map/map_queries.h"

namespace ndtom {

namespace {

void visitBlock(const CellIndex& block_index, const MapBlock& block,
                void (*visit)(void*, const CellView&), void* f) {
  if (block.known.none()) return;
  const CellStats* next = block.stats.data();  // cells with statistics come in offset order
  for (int i = 0; i < kBlockCells; ++i) {
    if (!block.known[i]) continue;
    visit(f, CellView{cellInBlock(block_index, i), block.logodds[i],
                      block.hasStats(i) ? next++ : nullptr});
  }
}

}  // namespace

bool MapBlock::eraseStats(int i) {
  const auto pos = stats.begin() + std::ptrdiff_t(statsPos(i));
  const bool gaussian = pos->hasGaussian();
  stats.erase(pos);
  has_stats[i >> 6] &= ~(uint64_t(1) << (i & 63));
  return gaussian;
}

NdtMap::~NdtMap() = default;
NdtMap::NdtMap(NdtMap&&) noexcept = default;
NdtMap& NdtMap::operator=(NdtMap&&) noexcept = default;

NdtMap::NdtMap(const MapOptions& options) : options_(options), geometry_(options.resolution) {
  validate(options_);
  touch();
}

void NdtMap::touch() {
  static std::atomic<uint64_t> last_revision{0};
  revision_ = last_revision.fetch_add(1, std::memory_order_relaxed) + 1;
  stats_changes_.from = stats_changes_.to = 0;  // unknown, unless an insertion sets them
  stats_changes_.blocks.clear();
}

// A copy's statistics arrays hold no spare room: their bytes are counted again.
NdtMap::NdtMap(const NdtMap& other)
    : options_(other.options_),
      geometry_(other.geometry_),
      grid_(other.grid_),
      num_cells_(other.num_cells_),
      revision_(other.revision_) {
  stats_bytes_ = memoryBytesCounted() - grid_.memoryBytes();
}

// Member by member: this map keeps its own scratch (and worker threads).
NdtMap& NdtMap::operator=(const NdtMap& other) {
  if (this == &other) return *this;
  options_ = other.options_;
  geometry_ = other.geometry_;
  grid_ = other.grid_;
  num_cells_ = other.num_cells_;
  revision_ = other.revision_;
  stats_bytes_ = memoryBytesCounted() - grid_.memoryBytes();
  return *this;
}

float NdtMap::clampLogOdds(double l) const {
  return ndtom::clampLogOdds(l, options_.occupancy);
}

size_t NdtMap::numGaussians() const {
  size_t n = 0;
  for (const auto& [block_index, block] : grid_.blocks())
    for (const CellStats& s : block->stats) n += s.hasGaussian();
  return n;
}

void NdtMap::visitCells(CellCallback visit, void* f) const {
  for (const auto& [block_index, block] : grid_.blocks()) visitBlock(block_index, *block, visit, f);
}

void NdtMap::visitCellsOrdered(CellCallback visit, void* f) const {
  std::vector<std::pair<CellIndex, const MapBlock*>> blocks;
  blocks.reserve(grid_.size());
  for (const auto& [block_index, block] : grid_.blocks())
    blocks.emplace_back(block_index, block.get());
  std::sort(blocks.begin(), blocks.end(),
            [](const auto& a, const auto& b) { return a.first < b.first; });
  for (const auto& [block_index, block] : blocks) visitBlock(block_index, *block, visit, f);
}

size_t NdtMap::numOccupied() const {
  size_t n = 0;
  forEachCell([&](const CellView& c) { n += cellState(*this, c) == CellState::Occupied; });
  return n;
}

std::optional<CellView> NdtMap::cell(const CellIndex& index) const {
  const MapBlock* block = grid_.find(blockOf(index));
  if (!block) return std::nullopt;
  const int i = offsetInBlock(index);
  if (!block->known[i]) return std::nullopt;
  return CellView{index, block->logodds[i], block->statsOf(i)};
}

std::optional<CellView> NdtMap::cellAt(const Eigen::Vector3d& point) const {
  if (!geometry_.inRange(point)) return std::nullopt;
  return cell(geometry_.cellOf(point));
}

std::optional<double> NdtMap::occupancyProbability(const Eigen::Vector3d& point) const {
  const auto c = cellAt(point);
  if (!c) return std::nullopt;
  return ndtom::occupancyProbability(c->logodds);
}

Gaussian NdtMap::gaussianOf(const CellView& c, Covariance covariance) const {
  Gaussian g;
  g.cell = c.index;
  g.n = c.stats->n;
  g.mean = geometry_.cellCenter(c.index) + c.stats->relative_mean;
  g.covariance = c.stats->covariance();
  if (covariance == Covariance::Regularized)
    g.covariance = regularizedCovariance(g.covariance, options_.regularization);
  return g;
}

std::optional<Gaussian> NdtMap::gaussian(const CellIndex& index, Covariance covariance) const {
  const auto c = cell(index);
  if (!c || !c->stats || !c->stats->hasGaussian()) return std::nullopt;
  return gaussianOf(*c, covariance);
}

size_t NdtMap::numBlocks() const {
  return grid_.size();
}

size_t NdtMap::memoryBytes() const {
  return grid_.memoryBytes() + stats_bytes_;
}

size_t NdtMap::memoryBytesCounted() const {
  size_t bytes = grid_.memoryBytes();
  for (const auto& [block_index, block] : grid_.blocks()) bytes += statsBytes(block->stats);
  return bytes;
}

void NdtMap::clear() {
  touch();
  grid_.clear();
  scratch_.reset();
  num_cells_ = 0;
  stats_bytes_ = 0;
}

void NdtMap::checkRoomForBlocks(size_t new_blocks, const char* what) const {
  const uint64_t need = grid_.memoryBytes() + new_blocks * grid_.kBytesPerBlock;
  if (need > options_.scan.memory_budget)
    throw MemoryBudgetError(
        std::string(what) + ": a map of " + std::to_string(grid_.size() + new_blocks) + " blocks",
        need, options_.scan.memory_budget);
}

bool NdtMap::setCell(const CellIndex& index, float logodds, const CellStats& stats) {
  if (!std::isfinite(logodds)) throw std::invalid_argument("setCell: non-finite log-odds");
  const float clamped = clampLogOdds(logodds);
  if (const char* problem = cellProblem(index, clamped, stats, options_))
    throw std::invalid_argument(std::string("setCell: ") + problem);
  touch();
  MapBlock* block = grid_.find(blockOf(index));
  if (!block) {
    checkRoomForBlocks(1, "setCell");
    block = &grid_.getOrCreate(blockOf(index));
  }
  const int i = offsetInBlock(index);
  const bool created = !block->known[i];
  if (created) {
    block->known.set(i);
    ++num_cells_;
  }
  block->logodds[i] = clamped;
  const size_t bytes_before = statsBytes(block->stats);
  if (stats.n == 0) {
    if (block->hasStats(i)) block->eraseStats(i);
  } else if (block->hasStats(i)) {
    block->stats[block->statsPos(i)] = stats;
  } else {
    block->stats.insert(block->stats.begin() + std::ptrdiff_t(block->statsPos(i)), stats);
    block->has_stats[i >> 6] |= uint64_t(1) << (i & 63);
  }
  stats_bytes_ += statsBytes(block->stats) - bytes_before;  // wraps back if it shrank
  return created;
}

void NdtMap::shrinkToFit() {
  stats_bytes_ = 0;
  for (auto& [index, block] : grid_.blocks()) {
    block->stats.shrink_to_fit();
    stats_bytes_ += statsBytes(block->stats);
  }
}

void NdtMap::merge(const NdtMap& other) {
  if (other.options_.resolution != options_.resolution)
    throw std::invalid_argument("merge: maps have different resolutions");
  touch();
  if (&other == this) {
    const NdtMap copy = other;
    merge(copy);
    return;
  }
  size_t new_blocks = 0;  // checked first: a merge stopped half-way would leave half a map
  for (const auto& [block_index, block] : other.grid_.blocks())
    new_blocks += !grid_.find(block_index);
  checkRoomForBlocks(new_blocks, "merge");
  other.forEachCell([&](const CellView& theirs) {
    const auto mine = cell(theirs.index);
    const double logodds = double(theirs.logodds) + (mine ? double(mine->logodds) : 0.0);
    CellStats stats = mine && mine->stats ? *mine->stats : CellStats{};
    if (theirs.stats) stats.merge(*theirs.stats);
    stats.clampMean(halfCell());
    if (options_.occupancy.enabled && clampLogOdds(logodds) <= 0.f) stats = CellStats{};
    setCell(
        theirs.index,
        float(std::clamp(logodds, options_.occupancy.logodds_min, options_.occupancy.logodds_max)),
        stats);
  });
  shrinkToFit();
}

NdtMap NdtMap::coarsened(int factor) const {
  if (factor < 1) throw std::invalid_argument("coarsened: factor must be >= 1");
  MapOptions coarse_options = options_;
  coarse_options.resolution = options_.resolution * factor;
  NdtMap coarse(coarse_options);
  const double r = options_.resolution;
  // In block order: a coarse cell spanning blocks merges its fine cells in an order that must
  // not depend on the hash table's history (RCU is exact but not associative in floating
  // point), so equal maps, e.g. a map and its saved and loaded copy, coarsen to equal bits.
  forEachCellOrdered([&](const CellView& fine) {
    const CellIndex index = cellwiseFloorDiv(fine.index, factor);
    const auto existing = coarse.cell(index);
    const float logodds = existing ? std::max(existing->logodds, fine.logodds) : fine.logodds;
    CellStats stats = existing && existing->stats ? *existing->stats : CellStats{};
    if (fine.stats) {
      // Fine centre minus coarse centre, from small integers: exact for dyadic resolutions.
      Eigen::Vector3d offset;
      for (int a = 0; a < 3; ++a)
        offset[a] = r * (double(fine.index[a] - index[a] * factor) + 0.5 - 0.5 * factor);
      stats.merge(fine.stats->shifted(-offset));
      stats.clampMean(coarse.halfCell());
    }
    coarse.setCell(index, logodds, stats);
  });
  coarse.shrinkToFit();
  return coarse;
}

}  // namespace ndtom
