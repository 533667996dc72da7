// Two clusters of points in two cells of a 0.5 m map: both cells must be occupied, and the
// Gaussian of one must equal the points' batch mean and covariance. The installed evaluation
// library scores the map against itself: a similarity of exactly 1.
#include <ndtom/map/ndt_map.h>
#include <ndtom_eval/map_similarity.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

int main() {
  ndtom::MapOptions options;
  options.resolution = 0.5;
  ndtom::NdtMap map(options);

  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0.05, 0.45);  // inside a cell, off its faces
  std::vector<Eigen::Vector3d> points, in_cell_111;
  for (int i = 0; i < 50; ++i) {
    in_cell_111.emplace_back(0.5 + u(rng), 0.5 + u(rng), 0.5 + u(rng));  // cell (1, 1, 1)
    points.push_back(in_cell_111.back());
    points.emplace_back(-0.5 + u(rng), u(rng), 1.0 + u(rng));  // cell (-1, 0, 2)
  }
  // From below in y: no ray to one cluster crosses the other's cell.
  map.insertScan(points, Eigen::Vector3d(0.75, -3.0, 0.75));

  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const auto& p : in_cell_111) mean += p;
  mean /= double(in_cell_111.size());
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  for (const auto& p : in_cell_111) covariance += (p - mean) * (p - mean).transpose();
  covariance /= double(in_cell_111.size() - 1);

  const auto g = map.gaussian(ndtom::CellIndex{1, 1, 1}, ndtom::Covariance::Exact);
  const ndtom::GaussianSet gaussians = ndtom::gaussianSetOf(map);
  const bool ok = map.numOccupied() == 2 && map.numGaussians() == 2 && g && g->n == 50 &&
                  (g->mean - mean).norm() < 1e-9 && (g->covariance - covariance).norm() < 1e-9 &&
                  ndtom::mapSimilarity(gaussians, gaussians) == 1.0;
  std::printf("occupied %zu, gaussians %zu, cell (1,1,1): n %u, mean error %.3g\n",
              map.numOccupied(), map.numGaussians(), g ? g->n : 0,
              g ? (g->mean - mean).norm() : NAN);
  std::puts(ok ? "core_user: ok" : "core_user: FAILED");
  return ok ? 0 : 1;
}
