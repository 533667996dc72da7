// One rule for what a cell may hold (cell_rules.h), applied alike by insertion, setCell(),
// saving and loading: everything a map can hold saves and loads back byte for byte, and a
// file holding anything else is refused even with a valid checksum. Files are written by
// hand (support/ndtom_file_builder.h), from the layout documented in map_io.h.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <tuple>
#include <utility>

#include "ndtom/files/map_io.h"
#include "ndtom/map/cell_rules.h"
#include "ndtom_internal/crc32.h"
#include "support/ndtom_file_builder.h"

using Eigen::Vector3d;
using ndtom::CellIndex;
using ndtom::CellStats;
using ndtom::MapOptions;
using ndtom::NdtMap;
using ndtom::testing::FileBuilder;

namespace {

constexpr int32_t kTop = ndtom::kMaxCellIndex - 1;  // the largest supported index

CellStats threePoints(double half) {
  std::vector<Vector3d> pts = {
      {0.1 * half, 0.2 * half, -0.3 * half}, {-0.5 * half, 0.4 * half, 0.1 * half}, {0.2, 0, 0}};
  pts[2] *= half;
  return CellStats::fromPoints(pts);
}

std::string loadError(const std::vector<uint8_t>& file) {
  try {
    ndtom::decodeMap(file.data(), file.size(), "crafted");
  } catch (const ndtom::MapFormatError& e) {
    return e.what();
  }
  return "loaded";
}

std::vector<uint8_t> oneCell(const CellIndex& c, float logodds, const CellStats& s,
                             const MapOptions& o = {}) {
  FileBuilder f(o);
  f.cells(1);
  f.cell(c, logodds, s);
  return f.finish();
}

}  // namespace

TEST(CellRules, HandWrittenVersion1FileLoadsAndReencodesToTheSameCells) {
  const MapOptions o;
  const CellStats s = threePoints(0.1);
  FileBuilder f(o);
  f.cells(2);
  f.cell({-kTop, kTop, -kTop}, -0.5f);  // in block order, as the encoder writes them
  f.cell({1, 2, 3}, 1.5f, s);
  const auto file = f.finish();
  const NdtMap map = ndtom::decodeMap(file.data(), file.size());
  ASSERT_EQ(map.numCells(), 2u);
  const auto far = map.cell({-kTop, kTop, -kTop});
  const auto near = map.cell({1, 2, 3});
  ASSERT_TRUE(far && near && near->stats);
  EXPECT_EQ(far->logodds, -0.5f);
  EXPECT_EQ(near->stats->n, s.n);
  EXPECT_EQ(std::memcmp(near->stats->relative_mean.data(), s.relative_mean.data(), 3 * 8), 0);
  EXPECT_EQ(std::memcmp(near->stats->scatter.data(), s.scatter.data(), 9 * 8), 0);
  // Saved again in the current format, which loads back to the same bytes.
  const auto again = ndtom::encodeMap(map);
  EXPECT_EQ(again[8], ndtom::kMapFormatVersion);
  EXPECT_EQ(ndtom::encodeMap(ndtom::decodeMap(again.data(), again.size())), again);
}

// Class 5 of issue #17: checksum-valid files whose values were silently taken.
TEST(CellRules, LoaderRefusesWhatNoMapCanHold) {
  const MapOptions o;
  const double half = 0.5 * o.resolution;
  const CellStats good = threePoints(half);
  ASSERT_EQ(loadError(oneCell({0, 0, 0}, 1.f, good)), "loaded");

  for (const double b : {0.5, 2.0, std::nan(""), -1.0, -0.0}) {
    FileBuilder f(o, "occupancy_enabled", b);
    f.cells(0);
    EXPECT_NE(loadError(f.finish()).find("occupancy_enabled: not 0 or 1"), std::string::npos)
        << "bool stored as " << b;
  }
  // -0 as ray mode 0 re-encoded as +0: found by fuzz_map_decoder.
  for (const double m : {-0.0, 0.5, 2.0}) {
    FileBuilder f(o, "ray_mode", m);
    f.cells(0);
    EXPECT_NE(loadError(f.finish()).find("ray_mode: unknown value"), std::string::npos) << m;
  }
  CellStats bad = good;
  bad.scatter(0, 1) = bad.scatter(1, 0) = 2 * std::sqrt(bad.scatter(0, 0) * bad.scatter(1, 1));
  EXPECT_NE(loadError(oneCell({0, 0, 0}, 1.f, bad)).find("not positive semi-definite"),
            std::string::npos);
  bad = good;
  bad.scatter(2, 2) = -1e-3;
  EXPECT_NE(loadError(oneCell({0, 0, 0}, 1.f, bad)).find("not positive semi-definite"),
            std::string::npos);
  // A negative spread along an axis, the others spreading nothing: every minor and the
  // determinant are 0, so only the diagonal shows it.
  bad = good;
  bad.scatter.setZero();
  bad.scatter(0, 0) = -1e-3;
  EXPECT_NE(loadError(oneCell({0, 0, 0}, 1.f, bad)).find("not positive semi-definite"),
            std::string::npos);
  bad = good;
  bad.relative_mean.x() = std::nextafter(half, 1.0);  // one ulp outside the closed cell
  EXPECT_NE(loadError(oneCell({0, 0, 0}, 1.f, bad)).find("mean outside its cell"),
            std::string::npos);
  bad.relative_mean.x() = half;  // on its face: inside
  EXPECT_EQ(loadError(oneCell({0, 0, 0}, 1.f, bad)), "loaded");
  // Issue #38: diag(1e308) loaded and then overflowed in coarsening. Two points on opposite
  // faces spread r²/2 in total, inside the limit of N·r²; more than that no points can.
  bad = good;
  bad.scatter = Eigen::Matrix3d::Identity() * 1e308;
  EXPECT_NE(loadError(oneCell({0, 0, 0}, 1.f, bad)).find("scatter wider than its cell"),
            std::string::npos);
  const CellStats faces = CellStats::fromPoints({{-half, -half, -half}, {half, half, half}});
  EXPECT_EQ(loadError(oneCell({0, 0, 0}, 1.f, faces)), "loaded");
  bad = faces;
  bad.scatter(1, 1) = std::nextafter(2 * o.resolution * o.resolution, 1e9);
  EXPECT_NE(loadError(oneCell({0, 0, 0}, 1.f, bad)).find("scatter wider than its cell"),
            std::string::npos);
  bad = good;
  bad.n = 1;
  EXPECT_NE(loadError(oneCell({0, 0, 0}, 1.f, bad)).find("one point with a non-zero scatter"),
            std::string::npos);
  EXPECT_NE(loadError(oneCell({0, 0, 0}, -0.1f, good)).find("statistics in an empty cell"),
            std::string::npos);
  EXPECT_NE(loadError(oneCell({0, 0, 0}, std::nanf(""), {})).find("non-finite log-odds"),
            std::string::npos);
  EXPECT_NE(loadError(oneCell({kTop + 1, 0, 0}, 1.f, {})).find("index outside"), std::string::npos);
  FileBuilder dup(o);
  dup.cells(2);
  dup.cell({4, 5, 6}, 1.f, good);
  dup.cell({4, 5, 6}, 2.f, good);
  EXPECT_NE(loadError(dup.finish()).find("duplicate cell"), std::string::npos);
}

// Class 4 of issue #17: setCell follows the loader's rule, and leaves the map as it was when
// it refuses. Before, setCell took a NaN log-odds (which saveMap wrote and loadMap refused)
// and refused the index -(2^30 - 1) that insertion produced.
TEST(CellRules, SetCellAppliesTheSameRule) {
  NdtMap map;
  const CellStats good = threePoints(0.1);
  map.setCell({0, 0, 0}, 1.f, good);
  const auto before = ndtom::encodeMap(map);
  CellStats one = good;
  one.n = 1;
  CellStats outside = good;
  outside.relative_mean.y() = -0.100001;
  for (const auto& [c, l, s] : std::vector<std::tuple<CellIndex, float, CellStats>>{
           {{1, 1, 1}, std::nanf(""), {}},
           {{1, 1, 1}, std::numeric_limits<float>::infinity(), {}},
           {{kTop + 1, 0, 0}, 1.f, {}},
           {{0, std::numeric_limits<int32_t>::min(), 0}, 1.f, {}},
           {{1, 1, 1}, -1.f, good},
           {{1, 1, 1}, 1.f, one},
           {{1, 1, 1}, 1.f, outside}}) {
    EXPECT_THROW(map.setCell(c, l, s), std::invalid_argument);
    EXPECT_EQ(ndtom::encodeMap(map), before);
  }
  EXPECT_TRUE(map.setCell({-kTop, -kTop, kTop}, 1.f, good));
  EXPECT_FALSE(map.setCell({-kTop, -kTop, kTop}, 2.f, good));  // known: replaced
  const auto bytes = ndtom::encodeMap(map);
  EXPECT_EQ(ndtom::encodeMap(ndtom::decodeMap(bytes.data(), bytes.size())), bytes);
}

// Everything insertion accepts saves and loads back: points in the outermost supported cells
// (index -(2^30 - 1) was accepted by insertion and refused by the loader), and points a few
// ulps below a cell's upper face far from the origin, whose mean came out just outside the
// cell (at 0.1 m, 145 of 2000 such maps could be saved but not loaded).
TEST(CellRules, EverythingInsertableRoundTrips) {
  for (const double r : {0.1, 0.3, 1.0}) {
    MapOptions o;
    o.resolution = r;
    o.scan.max_range = 10 * r;
    std::mt19937 rng(1);
    for (int k = 0; k < 400; ++k) {
      NdtMap map(o);
      double i = double(kTop - int32_t(rng() % 1000000));
      if (k % 2) i = -i;
      double x = std::nextafter((i + 1) * r, 0.0);
      for (int u = int(rng() % 3); u > 0; --u) x = std::nextafter(x, 0.0);
      const std::vector<Vector3d> pts = {{x, 0.05, 0.05}, {x, 0.06, 0.05}, {x, 0.05, 0.07}};
      map.insertScan(pts, Vector3d(x - 5 * r, 0.05, 0.05));
      ASSERT_GT(map.numCells(), 1u) << "r " << r << " k " << k << " x " << x;
      const auto bytes = ndtom::encodeMap(map);
      NdtMap loaded;
      ASSERT_NO_THROW(loaded = ndtom::decodeMap(bytes.data(), bytes.size()))
          << "r " << r << " x " << x;
      EXPECT_EQ(ndtom::encodeMap(loaded), bytes);
    }
    // The outermost cells, from inside: both faces of the supported range.
    NdtMap edge(o);
    const double lo = (-kTop + 0.5) * r, hi = (kTop + 0.5) * r;
    const auto report = edge.insertScan({{lo, lo, lo}, {hi, hi, hi}, {lo, hi, 0.1}},
                                        Vector3d(0.05, 0.05, 0.05), [&] {
                                          auto in = o.scan;
                                          in.max_range = std::numeric_limits<double>::infinity();
                                          return in;
                                        }());
    EXPECT_EQ(report.rejected_out_of_grid, 0u);
    edge.forEachCell(
        [](const ndtom::CellView& c) { EXPECT_TRUE(ndtom::isSupportedCell(c.index)); });
    EXPECT_FALSE(edge.geometry().inRange(Vector3d(-(kTop + 0.5) * r, 0, 0)));
    EXPECT_FALSE(edge.geometry().inRange(Vector3d((kTop + 1) * r, 0, 0)));
  }
}

// A cell's point count saturates at 2^32 - 1 instead of wrapping (merge, coarsening, or
// 4.3e9 points over many scans), and the saturated map still saves and loads.
TEST(CellRules, PointCountSaturates) {
  CellStats a = threePoints(0.1), b = threePoints(0.1);
  a.n = ndtom::kMaxCellPoints - 1;
  b.n = 5;
  a.merge(b);
  EXPECT_EQ(a.n, ndtom::kMaxCellPoints);  // was 3
  // S shrinks with N: the covariance is that of the exact merge of 2^32 + 3 points.
  CellStats c = threePoints(0.1), d = threePoints(0.1);
  c.n = ndtom::kMaxCellPoints - 1;
  d.n = 5;
  const double total = double(c.n) + d.n;
  const Eigen::Matrix3d unsaturated = c.scatter + d.scatter;  // same means: no cross term
  c.merge(d);
  EXPECT_TRUE(c.covariance().isApprox(unsaturated / (total - 1), 1e-12));
  NdtMap fine;
  CellStats big = threePoints(0.1);
  big.n = 3000000000u;
  for (const CellIndex& c : {CellIndex{0, 0, 0}, CellIndex{1, 0, 0}}) fine.setCell(c, 1.f, big);
  NdtMap merged = fine;
  merged.merge(fine);
  EXPECT_EQ(merged.cell({0, 0, 0})->stats->n, ndtom::kMaxCellPoints);
  const NdtMap coarse = fine.coarsened(2);
  EXPECT_EQ(coarse.cell({0, 0, 0})->stats->n, ndtom::kMaxCellPoints);
  for (const NdtMap* m : {&std::as_const(merged), &coarse}) {
    const auto bytes = ndtom::encodeMap(*m);
    EXPECT_EQ(ndtom::encodeMap(ndtom::decodeMap(bytes.data(), bytes.size())), bytes);
  }
}
