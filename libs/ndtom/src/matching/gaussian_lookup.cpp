#include "ndtom/matching/gaussian_lookup.h"

#include <algorithm>
#include <iterator>
#include <stdexcept>
#include <string>

#include "ndtom/map/eigenvalue_floor.h"
#include "ndtom/map/map_queries.h"

namespace ndtom {
namespace {

// Options may disable regularisation altogether; an exactly singular covariance (three
// collinear points) still needs an inverse, so eigenvalues never go below this (1 µm σ).
constexpr double kMinEigenvalue = 1e-12;  // m²

}  // namespace

namespace {

PreparedGaussian fromFloored(const Gaussian& g, const FlooredEigen& floored) {
  PreparedGaussian p;
  static_cast<Gaussian&>(p) = g;
  const Eigen::Vector3d& lambda = floored.values;  // ascending
  const Eigen::Matrix3d& v = floored.vectors;
  p.covariance = floored.matrix();
  p.information = v * lambda.cwiseInverse().asDiagonal() * v.transpose();
  p.max_variance = lambda[2];
  p.projection = v * (lambda[0] * lambda.cwiseInverse()).asDiagonal() * v.transpose();
  return p;
}

}  // namespace

PreparedGaussian prepared(const Gaussian& g) {
  return fromFloored(g, floorEigenvalues(g.covariance, kMinEigenvalue));
}

PreparedGaussian prepared(const Gaussian& exact, const Regularization& reg) {
  // Both floors at once: max(ratio·λ_max, abs) then 1e-12 is max(ratio·λ_max, abs, 1e-12).
  return fromFloored(exact,
                     floorEigenvalues(exact.covariance, std::max(reg.min_eigen_abs, kMinEigenvalue),
                                      reg.min_eigen_ratio));
}

GaussianLookup::GaussianLookup(const NdtMap& map, const LookupOptions& options)
    : geometry_(map.geometry()) {
  std::vector<PreparedGaussian> gaussians;
  gaussians.reserve(map.numGaussians());
  map.forEachCell([&](const CellView& c) {
    const bool wanted =
        options.occupied_only ? isOccupiedGaussian(map, c) : c.stats && c.stats->hasGaussian();
    if (!wanted) return;
    gaussians.push_back(
        prepared(map.gaussianOf(c, Covariance::Exact), map.options().regularization));
  });
  index(std::move(gaussians), options.nearest_means);
}

GaussianLookup::GaussianLookup(const GridGeometry& geometry, const std::vector<Gaussian>& gaussians,
                               const LookupOptions& options)
    : geometry_(geometry) {
  std::vector<PreparedGaussian> prepared_gaussians;
  prepared_gaussians.reserve(gaussians.size());
  for (const Gaussian& g : gaussians) prepared_gaussians.push_back(prepared(g));
  index(std::move(prepared_gaussians), options.nearest_means);
}

GaussianLookup::GaussianLookup(const GridGeometry& geometry,
                               std::vector<PreparedGaussian> gaussians,
                               const LookupOptions& options)
    : geometry_(geometry) {
  index(std::move(gaussians), options.nearest_means);
}

GaussianLookup::GaussianLookup(const GridGeometry& geometry, std::vector<GaussianBlock> blocks,
                               const LookupOptions& options)
    : geometry_(geometry) {
  for (size_t i = 0; i < blocks.size(); ++i) {
    GaussianBlock& b = blocks[i];
    if (i > 0 && !(blocks[i - 1].block < b.block))
      throw std::invalid_argument("GaussianLookup: blocks not in ascending block order");
    size_t bits = 0;
    for (const uint64_t word : b.cells) bits += popcount(word);
    if (bits != b.gaussians.size())
      throw std::invalid_argument("GaussianLookup: a block's bits (" + std::to_string(bits) +
                                  ") do not count its Gaussians (" +
                                  std::to_string(b.gaussians.size()) + ")");
    if (b.gaussians.empty()) continue;
    IndexBlock& block = by_cell_.getOrCreate(b.block);
    block.occupied = b.cells;
    block.gaussians = std::move(b.gaussians);
    block.countBefore();
    size_ += block.gaussians.size();
  }
  indexMeans(options.nearest_means);
}

void GaussianLookup::IndexBlock::reindex() {
  occupied.fill(0);
  for (const PreparedGaussian& g : gaussians) {
    const uint32_t offset = uint32_t(offsetInBlock(g.cell));
    occupied[offset >> 6] |= uint64_t(1) << (offset & 63);
  }
  countBefore();
}

void GaussianLookup::IndexBlock::countBefore() {
  uint32_t count = 0;
  for (size_t w = 0; w < kWords; ++w) {
    before[w] = uint16_t(count);
    count += popcount(occupied[w]);
  }
}

void GaussianLookup::index(std::vector<PreparedGaussian> gaussians, bool nearest_means) {
  // Sorted by key through an order of indices: moving 250-byte Gaussians while sorting
  // would cost more than the sort.
  std::vector<uint32_t> order(gaussians.size());
  for (uint32_t i = 0; i < order.size(); ++i) order[i] = i;
  std::sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) {
    return inBlockOrder(gaussians[a].cell, gaussians[b].cell);
  });
  for (size_t k = 0; k < order.size();) {
    const CellIndex key = blockOf(gaussians[order[k]].cell);
    size_t end = k;
    while (end < order.size() && blockOf(gaussians[order[end]].cell) == key) ++end;
    IndexBlock& block = by_cell_.getOrCreate(key);
    block.gaussians.reserve(end - k);
    for (; k < end; ++k) block.gaussians.push_back(std::move(gaussians[order[k]]));
    block.reindex();
  }
  size_ = gaussians.size();
  indexMeans(nearest_means);
}

void GaussianLookup::indexMeans(bool nearest_means) {
  nearest_means_ = nearest_means;
  if (!nearest_means) return;
  std::vector<Eigen::Vector3d> means;
  means.reserve(size_);
  mean_owners_.reserve(size_);
  forEachGaussian([&](const PreparedGaussian& g) {
    means.push_back(g.mean);
    mean_owners_.push_back(&g);
  });
  means_ = PointKdTree(means);
}

std::vector<std::pair<CellIndex, const GaussianLookup::IndexBlock*>> GaussianLookup::blocksInOrder()
    const {
  std::vector<std::pair<CellIndex, const IndexBlock*>> blocks;
  blocks.reserve(by_cell_.size());
  for (const auto& [key, block] : by_cell_.blocks()) blocks.emplace_back(key, block.get());
  std::sort(blocks.begin(), blocks.end(),
            [](const auto& a, const auto& b) { return a.first < b.first; });
  return blocks;
}

void GaussianLookup::update(std::vector<CellChange> changes) {
  if (nearest_means_)
    throw std::logic_error("GaussianLookup::update: a lookup with a k-d tree cannot be updated");
  const auto by_block = [](const CellChange& a, const CellChange& b) {
    return inBlockOrder(a.cell, b.cell);
  };
  if (!std::is_sorted(changes.begin(), changes.end(), by_block))  // MapPyramid's come sorted
    std::sort(changes.begin(), changes.end(), by_block);
  std::vector<PreparedGaussian> merged;
  for (size_t k = 0; k < changes.size();) {
    const CellIndex key = blockOf(changes[k].cell);
    IndexBlock* block = by_cell_.find(key);
    // The block's Gaussians and the changes, both in offset order, merged.
    merged.clear();
    size_t old = 0;
    const size_t old_count = block ? block->gaussians.size() : 0;
    for (; k < changes.size() && blockOf(changes[k].cell) == key; ++k) {
      const int offset = offsetInBlock(changes[k].cell);
      while (old < old_count && offsetInBlock(block->gaussians[old].cell) < offset)
        merged.push_back(std::move(block->gaussians[old++]));
      if (old < old_count && offsetInBlock(block->gaussians[old].cell) == offset) ++old;
      if (changes[k].gaussian) merged.push_back(std::move(*changes[k].gaussian));
    }
    while (old < old_count) merged.push_back(std::move(block->gaussians[old++]));
    size_ = size_ - old_count + merged.size();
    if (merged.empty()) {
      if (block) by_cell_.erase(key);
      continue;
    }
    if (!block) block = &by_cell_.getOrCreate(key);
    block->gaussians.assign(std::make_move_iterator(merged.begin()),
                            std::make_move_iterator(merged.end()));
    block->reindex();
  }
}

const PreparedGaussian* GaussianLookup::find(const CellIndex& cell) const {
  const IndexBlock* block = by_cell_.find(blockOf(cell));
  return block ? block->gaussianAt(uint32_t(offsetInBlock(cell))) : nullptr;
}

size_t GaussianLookup::memoryBytes() const {
  constexpr size_t kHeapBlockOverhead = 16;  // glibc's chunk header, per Gaussians array
  size_t bytes = by_cell_.memoryBytes() + mean_owners_.capacity() * sizeof(void*);
  for (const auto& [key, block] : by_cell_.blocks())
    bytes += block->gaussians.capacity() * sizeof(PreparedGaussian) + kHeapBlockOverhead;
  return bytes;
}

size_t GaussianLookup::maxBytesPerGaussian() {
  return sizeof(PreparedGaussian) + BlockGrid<IndexBlock>::kBytesPerBlock + 16 + sizeof(void*);
}

const PreparedGaussian* GaussianLookup::findAt(const Eigen::Vector3d& point) const {
  if (!geometry_.inRange(point)) return nullptr;
  return find(geometry_.cellOf(point));
}

}  // namespace ndtom
