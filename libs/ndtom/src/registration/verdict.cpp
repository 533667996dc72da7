#include "registration/verdict.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <sstream>
#include <vector>

#include "registration/newton_search.h"

namespace ndtom::registration {

namespace {

/// Whether `cell` is known free and none of the 26 around it is occupied: open space, where a
/// right pose puts only moving objects. (A free cell beside a surface is no evidence: rays
/// that grazed the surface freed it, and the scan's noise reaches it.)
bool inOpenFreeSpace(const NdtMap& map, const CellIndex& cell) {
  const auto c = map.cell(cell);
  if (!c || !(c->logodds < 0.f)) return false;
  for (int dz = -1; dz <= 1; ++dz)
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        const auto n = map.cell({cell.x + dx, cell.y + dy, cell.z + dz});
        if (n && n->logodds > 0.f) return false;
      }
  return true;
}

}  // namespace

SpaceFractions spaceFractions(const NdtMap& map, const NdtObjective& finest, const ScanLevel& level,
                              const Eigen::Isometry3d& pose, Threads threads) {
  SpaceFractions out;
  const size_t n = level.size();
  if (!map.options().occupancy.enabled || n == 0) return out;
  constexpr size_t kMinItemsPerThread = 512;  // each looks up a cell and maybe 27 more
  const size_t parts = threads.forItems(n, kMinItemsPerThread);
  std::vector<std::array<size_t, 2>> counts(parts, {0, 0});  // free, unknown (whole: any order)
  threads.pool.run(parts, [&](size_t t) {
    const auto [begin, end] = partRange(n, parts, t);
    size_t free = 0, unknown = 0;
    for (size_t i = begin; i < end; ++i) {
      const Eigen::Vector3d p =
          pose * (level.points.empty() ? level.gaussians[i].mean : level.points[i]);
      if (!map.geometry().inRange(p)) {
        unknown += !finest.matches(pose, i);
        continue;
      }
      // The map judges with its Gaussians and its free space: an occupied cell too thin to
      // hold a Gaussian (a sparse lidar's far surfaces) says nothing of where a point should be.
      const CellIndex cell = map.geometry().cellOf(p);
      const auto c = map.cell(cell);
      const bool judging = c && (c->logodds < 0.f || (c->stats && c->stats->hasGaussian()));
      if (!judging)
        unknown += !finest.matches(pose, i);
      else
        free += inOpenFreeSpace(map, cell);
    }
    counts[t] = {free, unknown};
  });
  size_t free = 0, unknown = 0;
  for (const auto& [f, u] : counts) {
    free += f;
    unknown += u;
  }
  out.free = double(free) / double(n);
  out.unknown = double(unknown) / double(n);
  return out;
}

PoseCovariance poseCovariance(const NdtObjective& finest, const Eigen::Isometry3d& pose,
                              const std::array<bool, 6>& free) {
  const PoseInformation info = finest.information(pose);
  // (Fixed parameters get a curvature on the scale of the others: out of the rank test.)
  const double typical = std::max(info.information.diagonal().maxCoeff(), 1e-300);
  const Eigen::SelfAdjointEigenSolver<Matrix6d> eig(restrictTo(info.information, free, typical));
  const size_t free_count = size_t(std::count(free.begin(), free.end(), true));
  PoseCovariance out;
  out.constrained = info.terms > free_count && eig.eigenvalues()[0] > 1e-9 * eig.eigenvalues()[5];
  if (out.constrained) {
    // Residuals as the map's Gaussians predict give χ² ≈ 3 per term: a scale near 1.
    const double scale = info.chi2 / double(3 * info.terms - free_count);
    out.covariance =
        restrictTo(scale * eig.eigenvectors() * eig.eigenvalues().cwiseInverse().asDiagonal() *
                       eig.eigenvectors().transpose(),
                   free, 0.0);
  } else {
    out.covariance = restrictTo(Matrix6d::Identity() * 1e6, free, 0.0);
  }
  return out;
}

std::string verdict(const RegistrationResult& r, bool constrained, const RegistrationOptions& o,
                    bool judge_free_space) {
  std::ostringstream why;
  if (!r.levels.back().converged) {
    why << "the finest level did not converge in " << o.max_iterations << " iterations";
  } else if (r.judged_fraction < o.min_judged_fraction) {
    why << "only " << r.judged_fraction << " of the scan lies where the map has looked "
        << "(min_judged_fraction " << o.min_judged_fraction << ")";
  } else if (r.matched_fraction < o.min_matched_fraction) {
    why << "only " << r.matched_fraction << " of the scan the map can judge matched it "
        << "(min_matched_fraction " << o.min_matched_fraction << ")";
  } else if (judge_free_space && r.free_fraction > o.max_free_fraction) {
    why << r.free_fraction << " of the scan lies in open space the map has seen free "
        << "(max_free_fraction " << o.max_free_fraction << ")";
  } else if (!constrained) {
    why << "the matched part of the scan does not constrain all six degrees of freedom";
  }
  return why.str();
}

}  // namespace ndtom::registration
