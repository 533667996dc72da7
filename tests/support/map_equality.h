// Two maps the same bit for bit: options and every cell (log-odds, counts, means, scatter).
#pragma once

#include <gtest/gtest.h>

#include <cstring>

#include "ndtom/map/ndt_map.h"

namespace ndtom::testing {

inline bool sameBits(const void* a, const void* b, size_t n) {
  return std::memcmp(a, b, n) == 0;
}

// memcmp, not ==: -0.0 and 0.0 differ, and a NaN would equal itself.
inline void expectBitIdentical(const NdtMap& a, const NdtMap& b) {
  ASSERT_EQ(a.numCells(), b.numCells());
  const MapOptions &oa = a.options(), &ob = b.options();
  for (const auto& [x, y] : {std::pair{oa.resolution, ob.resolution},
                             {oa.occupancy.p_hit, ob.occupancy.p_hit},
                             {oa.occupancy.p_miss, ob.occupancy.p_miss},
                             {oa.occupancy.logodds_min, ob.occupancy.logodds_min},
                             {oa.occupancy.logodds_max, ob.occupancy.logodds_max},
                             {oa.scan.max_range, ob.scan.max_range}})
    EXPECT_TRUE(sameBits(&x, &y, 8));
  EXPECT_EQ(oa.occupancy.enabled, ob.occupancy.enabled);
  size_t differ = 0;
  a.forEachCell([&](const CellView& ca) {
    const auto cb = b.cell(ca.index);
    if (!cb || !sameBits(&ca.logodds, &cb->logodds, 4) || !ca.stats != !cb->stats) {
      ++differ;
      return;
    }
    if (ca.stats &&
        (ca.stats->n != cb->stats->n ||
         !sameBits(ca.stats->relative_mean.data(), cb->stats->relative_mean.data(), 3 * 8) ||
         !sameBits(ca.stats->scatter.data(), cb->stats->scatter.data(), 9 * 8)))
      ++differ;
  });
  EXPECT_EQ(differ, 0u) << "cells that differ";
}

}  // namespace ndtom::testing
