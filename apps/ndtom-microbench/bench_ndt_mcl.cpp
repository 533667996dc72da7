// NDT-MCL's per-particle likelihood (ndtom/localization/ndt_mcl.h) against the point-based one
// (ndtom/matching/ndt_likelihood.h), on real lidar scans: a 0.2 m map of scans 0-29 and scan 35 as
// the observation, scored at 1000 poses scattered around its reference pose like the particles of
// a filter near convergence (σ 0.2 m in x and y, 0.05 m in z, 1° in roll and pitch, 3° in yaw).
// Needs the full sequence: NDTOM_MICROBENCH_DATA=../shared/datasets/balm-realworld. With the
// shipped ten scans the map is of scans 0-8 and scan 9 the observation.
#include <benchmark/benchmark.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <memory>

#include "microbench_data.h"
#include "ndtom/localization/ndt_mcl.h"
#include "ndtom/matching/gaussian_lookup.h"
#include "ndtom/matching/ndt_likelihood.h"

namespace {

using Eigen::Isometry3d;
using Eigen::Vector3d;

struct MclFixture {
  ndtom::NdtMap map{ndtom::microbench::benchOptions(0.2, ndtom::RayMode::PerPoint)};
  std::vector<Vector3d> scan;  ///< observation, sensor frame
  Isometry3d truth;
  std::vector<Isometry3d> particles;
  size_t map_scans = 0, observation = 0;

  MclFixture() {
    const auto& all = ndtom::microbench::realScans(36);
    observation = all.size() > 35 ? 35 : all.size() - 1;
    map_scans = std::min<size_t>(30, observation);
    for (size_t i = 0; i < map_scans; ++i) map.insertScan(all[i].points, all[i].origin);
    truth = all[observation].pose;
    for (const Vector3d& p : all[observation].points) scan.push_back(truth.inverse() * p);
    particles = ndtom::microbench::particlesAround(truth);
  }
};

const MclFixture& mclFixture() {
  static const MclFixture f;
  return f;
}

/// The scan's NDT, built once per observation. Argument: cell factor.
void BM_NdtMclScanNdt(benchmark::State& state) {
  const MclFixture& f = mclFixture();
  ndtom::ScanNdtOptions options;
  options.cell_size = 0.2 * double(state.range(0));
  for (auto _ : state) benchmark::DoNotOptimize(ndtom::buildScanNdt(f.scan, options));
  state.counters["scan_points"] = double(f.scan.size());
}

/// One particle's score. Arguments: scan cell edge and map level, both in 0.2 m map cells
/// (1: the map itself), scan Gaussians kept.
void BM_NdtMclPerParticle(benchmark::State& state) {
  const MclFixture& f = mclFixture();
  const int scan_factor = int(state.range(0)), map_factor = int(state.range(1));
  const ndtom::NdtMclMap level(map_factor == 1 ? f.map : f.map.coarsened(map_factor));
  ndtom::ScanNdtOptions options;
  options.cell_size = 0.2 * scan_factor;
  options.max_gaussians = size_t(state.range(2));
  const ndtom::ScanNdt scan = ndtom::buildScanNdt(f.scan, options);
  size_t matched = 0, scored = 0;
  for (auto _ : state)
    for (const Isometry3d& p : f.particles) {
      const auto score = ndtom::ndtMclLikelihood(level, scan, p, ndtom::NdtMclOptions{});
      matched += score.matched;
      scored += score.scored;
    }
  state.SetItemsProcessed(int64_t(state.iterations() * f.particles.size()));
  state.counters["scan_gaussians"] = double(scan.gaussians.size());
  state.counters["matched_share"] = double(matched) / double(std::max<size_t>(1, scored));
  state.counters["map_scans"] = double(f.map_scans);
  state.counters["observation"] = double(f.observation);
}

/// The point-based likelihood for comparison: the scan decimated as CNDTOccupancyMap's
/// default (1 point in 10), moved to each particle and scored (27 cells around each point).
void BM_PointsPerParticle(benchmark::State& state) {
  const MclFixture& f = mclFixture();
  const ndtom::GaussianLookup lookup(f.map);
  std::vector<Vector3d> decimated;
  for (size_t i = 0; i < f.scan.size(); i += 10) decimated.push_back(f.scan[i]);
  std::vector<Vector3d> moved(decimated.size());
  for (auto _ : state)
    for (const Isometry3d& p : f.particles) {
      for (size_t i = 0; i < decimated.size(); ++i) moved[i] = p * decimated[i];
      benchmark::DoNotOptimize(ndtom::scanLikelihood(lookup, moved, ndtom::LikelihoodOptions{}));
    }
  state.SetItemsProcessed(int64_t(state.iterations() * f.particles.size()));
  state.counters["scan_points"] = double(decimated.size());
}

BENCHMARK(BM_NdtMclScanNdt)->Arg(1)->Arg(2)->Arg(5)->Unit(benchmark::kMillisecond);
// The per-particle time is the reciprocal of items_per_second (1000 particles per iteration).
BENCHMARK(BM_NdtMclPerParticle)
    ->Args({2, 1, 100})
    ->Args({2, 1, 300})
    ->Args({2, 1, 1000})
    ->Args({1, 1, 300})
    ->Args({3, 1, 300})
    ->Args({5, 1, 300})
    ->Args({2, 2, 300})
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_PointsPerParticle)->Unit(benchmark::kMillisecond)->Iterations(3);

}  // namespace
