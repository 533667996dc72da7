#include "ndtom/ndt_map.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <stdexcept>

#include "scan_update.h"

namespace ndtom {

bool NdtMap::Block::eraseStats(int i) {
  const auto pos = stats.begin() + std::ptrdiff_t(statsPos(i));
  const bool gaussian = pos->hasGaussian();
  stats.erase(pos);
  has_stats[i >> 6] &= ~(uint64_t(1) << (i & 63));
  return gaussian;
}

NdtMap::Scratch::Scratch() : p_(std::make_unique<ScanScratch>()) {}
NdtMap::Scratch::~Scratch() = default;
NdtMap::Scratch::Scratch(Scratch&&) noexcept = default;
NdtMap::Scratch& NdtMap::Scratch::operator=(Scratch&&) noexcept = default;

NdtMap::NdtMap(const MapOptions& options) : options_(options), geometry_(options.resolution) {
  validate(options_);
  touch();
}

void NdtMap::touch() {
  static std::atomic<uint64_t> last_revision{0};
  revision_ = last_revision.fetch_add(1, std::memory_order_relaxed) + 1;
}

float NdtMap::clampLogOdds(double l) const {
  return float(std::clamp(l, options_.occupancy.logodds_min, options_.occupancy.logodds_max));
}

InsertionReport NdtMap::insertScan(const std::vector<Eigen::Vector3d>& points,
                                   const Eigen::Vector3d& sensor_origin) {
  return insertScan(points, sensor_origin, options_.insertion);
}

InsertionReport NdtMap::insertScan(const std::vector<Eigen::Vector3d>& points,
                                   const Eigen::Vector3d& sensor_origin,
                                   const InsertOptions& options) {
  touch();
  ScanUpdater updater(*this, options, scratch_.get());
  return updater.run(points, sensor_origin);
}

size_t NdtMap::numGaussians() const {
  size_t n = 0;
  for (const auto& [block_index, block] : grid_.blocks())
    for (const CellStats& s : block->stats) n += s.hasGaussian();
  return n;
}

size_t NdtMap::numOccupied() const {
  size_t n = 0;
  forEachCell([&](const CellView& c) { n += c.logodds > 0.f; });
  return n;
}

std::optional<CellView> NdtMap::cell(const CellIndex& index) const {
  const Block* block = grid_.find(blockOf(index));
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
  return 1.0 - 1.0 / (1.0 + std::exp(double(c->logodds)));
}

Gaussian NdtMap::gaussianOf(const CellView& c, bool regularized) const {
  Gaussian g;
  g.cell = c.index;
  g.n = c.stats->n;
  g.mean = geometry_.cellCenter(c.index) + c.stats->mean;
  g.covariance = c.stats->covariance();
  if (regularized) g.covariance = regularizedCovariance(g.covariance, options_.regularization);
  return g;
}

std::optional<Gaussian> NdtMap::gaussian(const CellIndex& index, bool regularized) const {
  const auto c = cell(index);
  if (!c || !c->stats || !c->stats->hasGaussian()) return std::nullopt;
  return gaussianOf(*c, regularized);
}

size_t NdtMap::memoryBytes() const {
  // glibc's malloc: a chunk header and rounding to 16 bytes for each statistics array.
  constexpr size_t kHeapBlockOverhead = 16;
  size_t bytes = grid_.memoryBytes();
  for (const auto& [block_index, block] : grid_.blocks())
    if (const size_t capacity = block->stats.capacity())
      bytes += capacity * sizeof(CellStats) + kHeapBlockOverhead;
  return bytes;
}

void NdtMap::clear() {
  touch();
  grid_.clear();
  scratch_ = Scratch();
  num_cells_ = 0;
}

void NdtMap::setCell(const CellIndex& index, float logodds, const CellStats& stats) {
  for (int a = 0; a < 3; ++a)
    if (!(std::abs(index[a]) < kMaxCellIndex - 1))
      throw std::invalid_argument("setCell: cell index outside the supported range");
  touch();
  Block& block = grid_.getOrCreate(blockOf(index));
  const int i = offsetInBlock(index);
  if (!block.known[i]) {
    block.known.set(i);
    ++num_cells_;
  }
  block.logodds[i] = clampLogOdds(logodds);
  if (stats.n == 0) {
    if (block.hasStats(i)) block.eraseStats(i);
  } else if (block.hasStats(i)) {
    block.stats[block.statsPos(i)] = stats;
  } else {
    block.stats.insert(block.stats.begin() + std::ptrdiff_t(block.statsPos(i)), stats);
    block.has_stats[i >> 6] |= uint64_t(1) << (i & 63);
  }
}

void NdtMap::shrinkToFit() {
  for (auto& [index, block] : grid_.blocks()) block->stats.shrink_to_fit();
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
  other.forEachCell([&](const CellView& theirs) {
    const auto mine = cell(theirs.index);
    const double logodds = double(theirs.logodds) + (mine ? double(mine->logodds) : 0.0);
    CellStats stats = mine && mine->stats ? *mine->stats : CellStats{};
    if (theirs.stats) stats.merge(*theirs.stats);
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
  forEachCell([&](const CellView& fine) {
    const CellIndex index{floorDiv(fine.index.x, factor), floorDiv(fine.index.y, factor),
                          floorDiv(fine.index.z, factor)};
    const auto existing = coarse.cell(index);
    const float logodds = existing ? std::max(existing->logodds, fine.logodds) : fine.logodds;
    CellStats stats = existing && existing->stats ? *existing->stats : CellStats{};
    if (fine.stats) {
      // Fine centre minus coarse centre, from small integers: exact for dyadic resolutions.
      Eigen::Vector3d offset;
      for (int a = 0; a < 3; ++a)
        offset[a] = r * (double(fine.index[a] - index[a] * factor) + 0.5 - 0.5 * factor);
      stats.merge(fine.stats->shifted(-offset));
    }
    coarse.setCell(index, logodds, stats);
  });
  coarse.shrinkToFit();
  return coarse;
}

}  // namespace ndtom
