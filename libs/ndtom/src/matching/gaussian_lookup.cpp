#include "ndtom/matching/gaussian_lookup.h"

#include <algorithm>

#include "ndtom/map/eigenvalue_floor.h"
#include "ndtom/map/map_queries.h"

namespace ndtom {
namespace {

// Options may disable regularisation altogether; an exactly singular covariance (three
// collinear points) still needs an inverse, so eigenvalues never go below this (1 µm σ).
constexpr double kMinEigenvalue = 1e-12;  // m²

PreparedGaussian prepare(const Gaussian& g) {
  PreparedGaussian p;
  p.cell = g.cell;
  p.n = g.n;
  p.mean = g.mean;
  const FlooredEigen floored = floorEigenvalues(g.covariance, kMinEigenvalue);
  const Eigen::Vector3d& lambda = floored.values;  // ascending
  const Eigen::Matrix3d& v = floored.vectors;
  p.covariance = floored.matrix();
  p.information = v * lambda.cwiseInverse().asDiagonal() * v.transpose();
  p.max_variance = lambda[2];
  p.projection = v * (lambda[0] * lambda.cwiseInverse()).asDiagonal() * v.transpose();
  return p;
}

}  // namespace

GaussianLookup::GaussianLookup(const NdtMap& map, const LookupOptions& options)
    : geometry_(map.geometry()) {
  gaussians_.reserve(map.numGaussians());
  map.forEachCell([&](const CellView& c) {
    const bool wanted =
        options.occupied_only ? isOccupiedGaussian(map, c) : c.stats && c.stats->hasGaussian();
    if (!wanted) return;
    gaussians_.push_back(prepare(map.gaussianOf(c, Covariance::Regularized)));
  });
  index(options.nearest_means);
}

GaussianLookup::GaussianLookup(const GridGeometry& geometry, const std::vector<Gaussian>& gaussians,
                               const LookupOptions& options)
    : geometry_(geometry) {
  gaussians_.reserve(gaussians.size());
  for (const Gaussian& g : gaussians) gaussians_.push_back(prepare(g));
  index(options.nearest_means);
}

void GaussianLookup::index(bool nearest_means) {
  gaussians_.shrink_to_fit();  // a level's bytes are counted per Gaussian (MapPyramid)
  std::sort(gaussians_.begin(), gaussians_.end(),
            [](const PreparedGaussian& a, const PreparedGaussian& b) { return a.cell < b.cell; });
  for (const PreparedGaussian& g : gaussians_) {
    const uint32_t offset = offsetInBlock(g.cell);
    by_cell_.getOrCreate(blockOf(g.cell)).occupied[offset >> 6] |= uint64_t(1) << (offset & 63);
  }
  uint32_t next = 0;  // each sparse block's share of slots_, in whatever order the hash keeps
  for (auto& [key, block] : by_cell_.blocks()) {
    uint32_t count = 0;
    for (size_t w = 0; w < IndexBlock::kWords; ++w) {
      block->before[w] = uint16_t(count);
      count += popcount(block->occupied[w]);
    }
    if (count >= kDenseFrom) {
      block->dense.assign(kBlockCells, kNone);
    } else {
      block->first = next;
      next += count;
    }
  }
  slots_.assign(next, kNone);
  for (uint32_t i = 0; i < gaussians_.size(); ++i) {
    const CellIndex& cell = gaussians_[i].cell;
    IndexBlock& block = *by_cell_.find(blockOf(cell));
    const uint32_t offset = offsetInBlock(cell);
    if (!block.dense.empty()) {
      block.dense[offset] = i;
    } else {
      const uint64_t bit = uint64_t(1) << (offset & 63);
      slots_[block.first + block.before[offset >> 6] +
             popcount(block.occupied[offset >> 6] & (bit - 1))] = i;
    }
  }
  if (!nearest_means) return;
  std::vector<Eigen::Vector3d> means;
  means.reserve(gaussians_.size());
  for (const PreparedGaussian& g : gaussians_) means.push_back(g.mean);
  means_ = PointKdTree(means);
}

const PreparedGaussian* GaussianLookup::find(const CellIndex& cell) const {
  const IndexBlock* block = by_cell_.find(blockOf(cell));
  if (!block) return nullptr;
  const uint32_t i = block->gaussianAt(offsetInBlock(cell), slots_);
  return i == kNone ? nullptr : &gaussians_[i];
}

size_t GaussianLookup::memoryBytes() const {
  size_t dense = 0;
  for (const auto& [key, block] : by_cell_.blocks()) dense += block->dense.capacity();
  return gaussians_.capacity() * sizeof(PreparedGaussian) +
         (slots_.capacity() + dense) * sizeof(uint32_t) + by_cell_.memoryBytes();
}

size_t GaussianLookup::maxBytesPerGaussian() {
  return sizeof(PreparedGaussian) + sizeof(uint32_t) + BlockGrid<IndexBlock>::kBytesPerBlock +
         kBlockCells * sizeof(uint32_t) / kDenseFrom;
}

const PreparedGaussian* GaussianLookup::findAt(const Eigen::Vector3d& point) const {
  if (!geometry_.inRange(point)) return nullptr;
  return find(geometry_.cellOf(point));
}

}  // namespace ndtom
