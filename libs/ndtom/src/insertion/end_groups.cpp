#include "insertion/end_groups.h"

#include <algorithm>

namespace ndtom {

void groupEnds(const ScanContext& scan, const ClassifiedPoints& points, const SortedRayEnds& sorted,
               GroupMeans means, EndGroups& out, InsertionReport& report) {
  out.hit_blocks.clear();
  out.has_means = false;
  const std::vector<uint64_t>& words = sorted.words;
  const size_t used = words.size();
  if (used == 0) {
    out.groups.clear();
    return;
  }
  // Groups are runs of equal keys. Threads split the sorted ends at run boundaries; each
  // gathers its ends (independent loads, instead of a dependent walk per group later) and
  // counts its runs, then fills its part of the group list.
  const size_t threads = scan.threadsFor(used, kMinPointsPerThread);
  out.sorted_ends.resize(used);
  std::vector<size_t> starts(threads + 1, used), runs(threads + 1, 0);
  starts[0] = 0;
  for (size_t t = 1; t < threads; ++t) {
    size_t start = std::max(partRange(used, threads, t).first, starts[t - 1]);
    while (start > 0 && start < used && sorted.keyOf(words[start]) == sorted.keyOf(words[start - 1]))
      ++start;
    starts[t] = start;
  }
  scan.pool.run(threads, [&](size_t t) {
    constexpr size_t kAhead = 16;  // the loads are random: start them early
    const size_t begin = starts[t], end = starts[t + 1];
    for (size_t i = begin; i < end; ++i) {
      if (i + kAhead < end) __builtin_prefetch(&points.ends[sorted.pointOf(words[i + kAhead])]);
      out.sorted_ends[i] = points.ends[sorted.pointOf(words[i])];
    }
    size_t count = 0;
    for (size_t i = begin; i < end; ++i)
      count += i == begin || sorted.keyOf(words[i]) != sorted.keyOf(words[i - 1]);
    runs[t + 1] = count;
  });
  for (size_t t = 0; t < threads; ++t) runs[t + 1] += runs[t];
  out.groups.resize(runs[threads]);  // every field is written below: zeroes only what it grows
  out.has_means = means == GroupMeans::Compute;
  // Each thread also lists the hit blocks of its groups; a block cut by a part's boundary
  // is joined below.
  if (out.part_hit_blocks.size() < threads) out.part_hit_blocks.resize(threads);
  std::vector<size_t> part_hits(threads, 0);
  scan.pool.run(threads, [&](size_t t) {
    const GridGeometry& geometry = scan.geometry;
    size_t group = runs[t];
    for (size_t i = starts[t]; i < starts[t + 1]; ++group) {
      EndGroup& g = out.groups[group];
      const uint64_t key = sorted.keyOf(words[i]);
      g.begin = uint32_t(i);
      while (i < starts[t + 1] && sorted.keyOf(words[i]) == key) ++i;
      g.count = uint32_t(i - g.begin);
      g.hit = SortedRayEnds::isHit(key);
      // The cell again from the sorted end (read in a row), not end_cells (a random access).
      g.cell = geometry.cellOf(out.sorted_ends[g.begin]);
      g.relative_mean = g.mean_end = Eigen::Vector3d::Zero();
      if (!out.has_means) continue;
      // One ray per group, to the mean of its ends.
      const Eigen::Vector3d centre = geometry.cellCenter(g.cell);
      for (uint32_t k = g.begin; k < g.begin + g.count; ++k)
        g.relative_mean += out.sorted_ends[k] - centre;
      g.relative_mean /= double(g.count);
      g.mean_end = centre + g.relative_mean;
    }
    // Hit cells and their blocks, from the keys.
    std::vector<HitBlock>& blocks = out.part_hit_blocks[t];
    blocks.clear();
    uint64_t last_block = 0;  // block number of blocks.back()
    size_t hits = 0;          // written once: neighbouring threads' counts share a line
    for (size_t k = runs[t]; k < runs[t + 1]; ++k) {
      if (!out.groups[k].hit) continue;
      ++hits;
      const uint64_t dense = SortedRayEnds::denseIndex(sorted.keyOf(words[out.groups[k].begin]));
      const uint64_t block = dense / kBlockCells;
      if (blocks.empty() || block != last_block) {
        blocks.push_back({k, 0, {}, block});
        last_block = block;
      }
      HitBlock& h = blocks.back();
      h.last_group = k + 1;
      const uint64_t offset = dense % kBlockCells;
      h.hits[offset / 64] |= uint64_t(1) << (offset % 64);
    }
    part_hits[t] = hits;
  });
  for (size_t t = 0; t < threads; ++t) report.cells_hit += part_hits[t];
  if (threads == 1) {
    out.hit_blocks.swap(out.part_hit_blocks[0]);
    return;
  }
  for (size_t t = 0; t < threads; ++t) {
    for (const HitBlock& h : out.part_hit_blocks[t]) {
      if (!out.hit_blocks.empty() && out.hit_blocks.back().number == h.number) {
        HitBlock& joined = out.hit_blocks.back();
        joined.last_group = h.last_group;
        for (size_t w = 0; w < h.hits.size(); ++w) joined.hits[w] |= h.hits[w];
      } else {
        out.hit_blocks.push_back(h);
      }
    }
  }
}

}  // namespace ndtom
