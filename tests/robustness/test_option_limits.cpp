// Bad option values are refused when the map is made, with a message naming the option.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>

#include "ndtom/map/ndt_map.h"

namespace {

void expectRejected(const std::function<void(ndtom::MapOptions&)>& spoil, const char* option) {
  ndtom::MapOptions o;
  spoil(o);
  try {
    ndtom::NdtMap map(o);
    ADD_FAILURE() << option << ": accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(std::string(e.what()).rfind(option, 0), 0u) << e.what();
  }
}

}  // namespace

TEST(OptionLimits, AbsurdValuesAreRefusedNamingTheOption) {
  const double nan = std::nan(""), inf = INFINITY;
  for (const double r : {0.0, -0.1, nan, inf, 1e-4, 5e3})
    expectRejected([r](ndtom::MapOptions& o) { o.resolution = r; }, "resolution");
  // Probabilities outside (0, 1) or on the wrong side of 0.5.
  for (const double p : {0.5, 0.4, 1.0, 0.0, nan, 1.5})
    expectRejected([p](ndtom::MapOptions& o) { o.occupancy.p_hit = p; }, "p_hit");
  for (const double p : {0.5, 0.6, 0.0, -0.1, nan})
    expectRejected([p](ndtom::MapOptions& o) { o.occupancy.p_miss = p; }, "p_miss");
  for (const double l : {0.0, 1.0, -inf, nan})
    expectRejected([l](ndtom::MapOptions& o) { o.occupancy.logodds_min = l; }, "logodds_min");
  for (const double l : {0.0, -1.0, inf, nan})
    expectRejected([l](ndtom::MapOptions& o) { o.occupancy.logodds_max = l; }, "logodds_max");
  for (const double m : {-1.0, nan, inf})
    expectRejected([m](ndtom::MapOptions& o) { o.scan.min_range = m; }, "min_range");
  for (const double m : {0.0, -5.0, nan})
    expectRejected([m](ndtom::MapOptions& o) { o.scan.max_range = m; }, "max_range");
  expectRejected(
      [](ndtom::MapOptions& o) {
        o.scan.min_range = 10;
        o.scan.max_range = 5;
      },
      "max_range");
  expectRejected([](ndtom::MapOptions& o) { o.scan.threads = 0; }, "threads");
  expectRejected([](ndtom::MapOptions& o) { o.scan.memory_budget = 999999; }, "memory_budget");
  expectRejected([](ndtom::MapOptions& o) { o.scan.ray_mode = ndtom::RayMode(7); }, "ray_mode");
  expectRejected([](ndtom::MapOptions& o) { o.regularization.min_eigen_ratio = 2; },
                 "min_eigen_ratio");
  expectRejected([](ndtom::MapOptions& o) { o.regularization.min_eigen_abs = -1; },
                 "min_eigen_abs");
  // Issue #38: a floor above r² makes every Gaussian wider than its cell (and its picture
  // ellipse wider than the picture); it is refused before any work.
  for (const double m : {0.04 * 1.0001, 1e3, 1e300, inf, nan})
    expectRejected(
        [m](ndtom::MapOptions& o) {
          o.resolution = 0.2;
          o.regularization.min_eigen_abs = m;
        },
        "min_eigen_abs");
  EXPECT_THROW(ndtom::rayModeFromString("fast"), std::invalid_argument);
}

TEST(OptionLimits, TheDefaultsAndTheBoundsThemselvesAreAccepted) {
  EXPECT_NO_THROW(ndtom::NdtMap(ndtom::MapOptions{}));
  ndtom::MapOptions o;
  o.resolution = ndtom::kMinResolution;
  EXPECT_NO_THROW(ndtom::NdtMap{o});
  o.resolution = ndtom::kMaxResolution;
  EXPECT_NO_THROW(ndtom::NdtMap{o});
  o.resolution = 0.2;
  o.regularization.min_eigen_abs = 0.2 * 0.2;
  EXPECT_NO_THROW(ndtom::NdtMap{o});
}
