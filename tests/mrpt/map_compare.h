// Compares two NDT-OMs built from the same data through different float/double paths
// (MRPT stores points as float): a point lying within rounding distance of a cell face may
// land in the neighbouring cell, so a tiny fraction of cells may differ; everything else
// must agree closely.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <iostream>

#include "ndtom/map/ndt_map.h"

namespace ndtom::testing {

struct MapDifference {
  size_t cells = 0;            ///< cells of `a`
  size_t unmatched = 0;        ///< cells in only one of the maps
  size_t count_differs = 0;    ///< common cells with a different N
  size_t logodds_differs = 0;  ///< common cells whose log-odds differ by more than 1e-4
  double max_mean_error = 0;   ///< over common cells with equal N ≥ 3 (m)
  double max_cov_error = 0;    ///< same, covariance (m²)
};

inline MapDifference compareMaps(const NdtMap& a, const NdtMap& b) {
  MapDifference d;
  d.cells = a.numCells();
  size_t common = 0;
  a.forEachCell([&](const CellView& ca) {
    const auto cb = b.cell(ca.index);
    if (!cb) return;
    ++common;
    if (std::abs(ca.logodds - cb->logodds) > 1e-4f) ++d.logodds_differs;
    const uint32_t na = ca.stats ? ca.stats->n : 0, nb = cb->stats ? cb->stats->n : 0;
    if (na != nb) {
      ++d.count_differs;
      return;
    }
    if (na < 3) return;
    const Gaussian ga = a.gaussianOf(ca, Covariance::Exact), gb = b.gaussianOf(*cb, Covariance::Exact);
    d.max_mean_error = std::max(d.max_mean_error, (ga.mean - gb.mean).norm());
    d.max_cov_error = std::max(d.max_cov_error, (ga.covariance - gb.covariance).norm());
  });
  d.unmatched = (a.numCells() - common) + (b.numCells() - common);
  return d;
}

/// At most `fraction` of the cells may differ in membership, count or occupancy.
inline void expectNearlySameMaps(const NdtMap& a, const NdtMap& b, double fraction = 1e-3) {
  const MapDifference d = compareMaps(a, b);
  ASSERT_GT(d.cells, 0u);
  std::cout << "[ compare  ] " << d.cells << " cells: " << d.unmatched << " unmatched, "
            << d.count_differs << " with another N, " << d.logodds_differs
            << " with other log-odds; max mean error " << d.max_mean_error
            << " m, max covariance error " << d.max_cov_error << " m²\n";
  const double allowed = fraction * double(d.cells) + 2;
  EXPECT_LE(d.unmatched, allowed) << "of " << d.cells << " cells";
  EXPECT_LE(d.count_differs, allowed) << "of " << d.cells << " cells";
  EXPECT_LE(d.logodds_differs, allowed) << "of " << d.cells << " cells";
  EXPECT_LT(d.max_mean_error, 1e-4);
  EXPECT_LT(d.max_cov_error, 1e-5);
  EXPECT_NEAR(double(a.numGaussians()), double(b.numGaussians()), allowed);
}

}  // namespace ndtom::testing
