// The installed map builder from outside the project: CMetricMapBuilderNDT through MRPT's base
// class, configured by the installed ndtom-slam.ini (argv[1]), on laser scans of a 10 m x 6 m
// room taken 0.2 m apart. Exit status 0 when every scan is tracked and the map has Gaussians.
#include <mrpt/config/CConfigFile.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt_ndtom/CMetricMapBuilderNDT.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace {

// A 360° scan from (x, 0) inside the room [-5, 5] x [-3, 3], one ray per degree.
mrpt::obs::CObservation2DRangeScan::Ptr roomScan(double x, int index) {
  auto scan = mrpt::obs::CObservation2DRangeScan::Create();
  scan->aperture = float(2 * M_PI);
  scan->rightToLeft = true;
  scan->resizeScan(360);
  for (size_t i = 0; i < 360; ++i) {
    const double a = -M_PI + 2 * M_PI * double(i) / 360;
    const double dx = std::cos(a), dy = std::sin(a);
    const double tx = dx > 0 ? (5 - x) / dx : dx < 0 ? (-5 - x) / dx : 1e9;
    const double ty = dy > 0 ? 3 / dy : dy < 0 ? -3 / dy : 1e9;
    scan->setScanRange(i, float(std::min(tx, ty)));
    scan->setScanRangeValidity(i, true);
  }
  scan->timestamp = mrpt::Clock::fromDouble(1000.0 + index);
  return scan;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) return 1;
  mrpt_ndtom::CMetricMapBuilderNDT ndt;
  ndt.NDT_options.loadFromConfigFile(mrpt::config::CConfigFile(argv[1]), "NDTSLAM");
  mrpt::slam::CMetricMapBuilder& builder = ndt;
  builder.initialize();
  for (int i = 0; i < 10; ++i) ndt.processObservation(roomScan(0.2 * i, i));
  size_t lost = 0;
  for (const auto& step : ndt.getSteps()) lost += step.outcome == ndtom::OnlineOutcome::Lost;
  const auto map = builder.getCurrentlyBuiltMetricMap()->mapByClass<mrpt_ndtom::CNDTOccupancyMap>();
  const double x = builder.getCurrentPoseEstimation()->getMeanVal().x();
  std::printf("%zu scans, %zu lost, %zu Gaussians, last x %.3f m (true 1.8 m)\n",
              ndt.getSteps().size(), lost, map ? map->ndtMap().numGaussians() : 0, x);
  return ndt.getSteps().size() == 10 && lost == 0 && map && map->ndtMap().numGaussians() > 0 &&
                 std::abs(x - 1.8) < 0.1
             ? 0
             : 1;
}
