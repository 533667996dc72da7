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
  std::sort(gaussians_.begin(), gaussians_.end(),
            [](const PreparedGaussian& a, const PreparedGaussian& b) { return a.cell < b.cell; });
  for (uint32_t i = 0; i < gaussians_.size(); ++i) {
    const CellIndex& cell = gaussians_[i].cell;
    by_cell_.getOrCreate(blockOf(cell)).index[offsetInBlock(cell)] = i;
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
  const uint32_t i = block->index[offsetInBlock(cell)];
  return i == kNone ? nullptr : &gaussians_[i];
}

const PreparedGaussian* GaussianLookup::findAt(const Eigen::Vector3d& point) const {
  if (!geometry_.inRange(point)) return nullptr;
  return find(geometry_.cellOf(point));
}

}  // namespace ndtom
