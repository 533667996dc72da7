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
  uint32_t next = 0;  // each block's share of slots_, in whatever order the hash keeps
  for (auto& [key, block] : by_cell_.blocks()) {
    block->first = next;
    uint16_t count = 0;
    for (size_t w = 0; w < IndexBlock::kWords; ++w) {
      block->before[w] = count;
      count = uint16_t(count + __builtin_popcountll(block->occupied[w]));
    }
    next += count;
  }
  slots_.assign(gaussians_.size(), kNone);
  for (uint32_t i = 0; i < gaussians_.size(); ++i) {
    const CellIndex& cell = gaussians_[i].cell;
    slots_[by_cell_.find(blockOf(cell))->slot(offsetInBlock(cell))] = i;
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
  const uint32_t s = block->slot(offsetInBlock(cell));
  return s == kNone ? nullptr : &gaussians_[slots_[s]];
}

size_t GaussianLookup::memoryBytes() const {
  return gaussians_.capacity() * sizeof(PreparedGaussian) +
         slots_.capacity() * sizeof(uint32_t) + by_cell_.memoryBytes();
}

size_t GaussianLookup::maxBytesPerGaussian() {
  return sizeof(PreparedGaussian) + sizeof(uint32_t) + BlockGrid<IndexBlock>::kBytesPerBlock;
}

const PreparedGaussian* GaussianLookup::findAt(const Eigen::Vector3d& point) const {
  if (!geometry_.inRange(point)) return nullptr;
  return find(geometry_.cellOf(point));
}

}  // namespace ndtom
