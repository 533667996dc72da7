// The per-particle likelihood as MRPT's particle filters pay it: CMultiMetricMap holding a
// CNDTOccupancyMap, computeObservationLikelihood(observation, particle pose) called once per
// particle (CMonteCarloLocalization3D does exactly this), NdtMcl method with the options of
// share/mrpt/pf-localization-lidar_ndtom.ini. Same data and particles as bench_ndt_mcl.cpp:
// the scan NDT is built on the first call and then found in the map's cache, the map table
// once. Built only with the MRPT plugin.
#include <benchmark/benchmark.h>
#include <mrpt/maps/CMultiMetricMap.h>
#include <mrpt/maps/CSimplePointsMap.h>
#include <mrpt/obs/CObservationPointCloud.h>

#include "microbench_data.h"
#include "mrpt_ndtom/CNDTOccupancyMap.h"

namespace {

using Eigen::Isometry3d;
using Eigen::Vector3d;

mrpt::poses::CPose3D toPose(const Isometry3d& t) {
  mrpt::math::CMatrixDouble44 m;
  m.asEigen() = t.matrix();
  return mrpt::poses::CPose3D(m);
}

struct MrptFixture {
  mrpt::maps::CMultiMetricMap maps;
  mrpt::obs::CObservationPointCloud observation;
  std::vector<mrpt::poses::CPose3D> particles;

  MrptFixture() {
    const auto& all = ndtom::microbench::realScans(36);
    const size_t scan = all.size() > 35 ? 35 : all.size() - 1;
    auto map = mrpt_ndtom::CNDTOccupancyMap::Create(0.2);
    map->insertionOptions.scan.max_range = 30.0;
    map->likelihoodOptions.likelihood_method =
        mrpt_ndtom::CNDTOccupancyMap::TLikelihoodMethod::NdtMcl;
    map->likelihoodOptions.outlier_likelihood = 0.1;
    map->likelihoodOptions.max_range = 30.0;
    map->likelihoodOptions.scale = 0.2;
    for (size_t i = 0; i < std::min<size_t>(30, scan); ++i)
      map->insertPoints(all[i].points, all[i].origin);
    maps.maps.push_back(map);

    const Isometry3d truth = all[scan].pose;
    auto cloud = mrpt::maps::CSimplePointsMap::Create();
    for (const Vector3d& p : all[scan].points) {
      const Vector3d q = truth.inverse() * p;
      cloud->insertPoint(float(q.x()), float(q.y()), float(q.z()));
    }
    observation.pointcloud = cloud;

    for (const Isometry3d& p : ndtom::microbench::particlesAround(truth))
      particles.push_back(toPose(p));
    maps.computeObservationLikelihood(observation, particles[0]);  // NDTs built
  }
};

MrptFixture& mrptFixture() {
  static MrptFixture f;
  return f;
}

void BM_MrptNdtMclPerParticle(benchmark::State& state) {
  MrptFixture& f = mrptFixture();
  double sum = 0;
  for (auto _ : state)
    for (const auto& p : f.particles) sum += f.maps.computeObservationLikelihood(f.observation, p);
  benchmark::DoNotOptimize(sum);
  state.SetItemsProcessed(int64_t(state.iterations() * f.particles.size()));
}

BENCHMARK(BM_MrptNdtMclPerParticle)->Unit(benchmark::kMillisecond);

}  // namespace
