// Paper Sec. III-B / IV-B-2: a coarse map derived from a fine one by RCU (NdtMap::coarsened)
// against a batch map built directly at the coarse resolution from the same points.
#include <algorithm>
#include <cmath>

#include "experiments.h"
#include "ndtom_eval/batch_ndt.h"
#include "top_view.h"

namespace ndtom::eval {

namespace {

/// How far a derived map's statistics are from the batch statistics, cell by cell.
struct StatsDifference {
  size_t batch_cells = 0;                   ///< cells with points in the batch map
  size_t count_mismatches = 0;              ///< cells whose N differs (or that are missing)
  double max_mean_diff = 0;                 ///< m, over cells with equal N
  double max_relative_covariance_diff = 0;  ///< ‖ΔP‖ / ‖P‖ (Frobenius), cells with N ≥ 3
};

StatsDifference compareWithBatch(const NdtMap& derived, const CellStatsMap& batch) {
  StatsDifference d;
  d.batch_cells = batch.size();
  for (const auto& [index, expected] : batch) {
    const auto cell = derived.cell(index);
    if (!cell || !cell->stats || cell->stats->n != expected.n) {
      ++d.count_mismatches;
      continue;
    }
    const CellStats& got = *cell->stats;
    d.max_mean_diff =
        std::max(d.max_mean_diff, (got.relative_mean - expected.relative_mean).norm());
    if (!expected.hasGaussian()) continue;
    const double scale = std::max(expected.covariance().norm(), 1e-300);
    d.max_relative_covariance_diff = std::max(
        d.max_relative_covariance_diff, (got.covariance() - expected.covariance()).norm() / scale);
  }
  // Cells with statistics that the batch map does not have at all.
  derived.forEachCell([&](const CellView& c) {
    if (c.stats && !batch.count(c.index)) ++d.count_mismatches;
  });
  return d;
}

void drawByHeight(EvalContext& ctx, const NdtMap& map, const std::string& file) {
  std::vector<Gaussian> gaussians;
  std::vector<Eigen::Vector3d> extent;
  map.forEachGaussian([&](const Gaussian& g) {
    gaussians.push_back(g);
    extent.push_back(g.mean);
  });
  if (gaussians.empty()) return;
  // Colour range: 2nd to 98th percentile of the heights, so a few outliers do not wash it out.
  std::vector<double> z;
  for (const Gaussian& g : gaussians) z.push_back(g.mean.z());
  std::sort(z.begin(), z.end());
  const double z_lo = z[z.size() / 50], z_hi = z[z.size() - 1 - z.size() / 50];
  TopView view(extent);
  view.drawGaussiansByHeight(gaussians, z_lo, std::max(z_hi, z_lo + 0.1));
  char title[96];
  std::snprintf(title, sizeof(title), "NDT-OM %.2f m: %zu Gaussians (1-sigma, top view)",
                map.geometry().resolution(), gaussians.size());
  view.drawLegend({{title, viridis(0.5)}});
  view.drawHeightBar(z_lo, std::max(z_hi, z_lo + 0.1));
  view.write(ctx.output(file));
}

void addRow(CsvTable& table, EvalContext& ctx, const std::string& name, const NdtMap& map,
            const GaussianSet& batch, const StatsDifference* diff) {
  const GaussianSet set = gaussianSetOf(map, ctx.floor);
  const double nan = std::nan("");
  table.addRow({name, map.geometry().resolution(), map.numGaussians(), mapSimilarity(set, batch),
                diff ? double(diff->count_mismatches) : nan, diff ? diff->max_mean_diff : nan,
                diff ? diff->max_relative_covariance_diff : nan});
}

}  // namespace

void runMultiResolution(EvalContext& ctx, const std::vector<Cloud>& clouds,
                        const MappingMaps& maps) {
  const int k = ctx.options.coarsening;
  const NdtMap recursive_coarse = maps.recursive.coarsened(k);
  const NdtMap ndtom_coarse = maps.ndtom.coarsened(k);
  // The batch maps use exactly the derived maps' geometries (0.3·3 in floating point).
  const GridGeometry& fine = maps.recursive.geometry();
  const GridGeometry& coarse = recursive_coarse.geometry();
  const std::vector<Eigen::Vector3d> points = allPoints(clouds);
  const CellStatsMap batch_fine = batchNdt(points, fine);
  const CellStatsMap batch_coarse = batchNdt(points, coarse);
  const GaussianSet batch_fine_set = gaussianSetOf(batch_fine, fine, ctx.floor);
  const GaussianSet batch_coarse_set = gaussianSetOf(batch_coarse, coarse, ctx.floor);

  const StatsDifference rec = compareWithBatch(recursive_coarse, batch_coarse);
  const StatsDifference om = compareWithBatch(ndtom_coarse, batch_coarse);
  CsvTable table({"map", "resolution", "gaussians", "similarity_to_batch", "cells_n_mismatch",
                  "max_mean_diff_m", "max_relative_covariance_diff"});
  addRow(table, ctx, "recursive_fine", maps.recursive, batch_fine_set, nullptr);
  addRow(table, ctx, "recursive_derived", recursive_coarse, batch_coarse_set, &rec);
  addRow(table, ctx, "ndtom_fine", maps.ndtom, batch_fine_set, nullptr);
  addRow(table, ctx, "ndtom_derived", ndtom_coarse, batch_coarse_set, &om);
  table.addRow({"batch_fine", fine.resolution(), batch_fine_set.size(), 1.0, 0, 0.0, 0.0});
  table.addRow({"batch_coarse", coarse.resolution(), batch_coarse_set.size(), 1.0, 0, 0.0, 0.0});
  table.write(ctx.output("multires.csv"));

  ctx.summary.add("multires_ndtom_fine_gaussians", maps.ndtom.numGaussians());
  ctx.summary.add("multires_ndtom_derived_gaussians", ndtom_coarse.numGaussians());
  ctx.summary.add("multires_recursive_fine_gaussians", maps.recursive.numGaussians());
  ctx.summary.add("multires_recursive_derived_gaussians", recursive_coarse.numGaussians());
  ctx.summary.add("multires_batch_coarse_gaussians", batch_coarse_set.size());
  ctx.summary.add("multires_recursive_derived_cells_n_mismatch", rec.count_mismatches);
  ctx.summary.add("multires_recursive_derived_max_mean_diff_m", rec.max_mean_diff);
  ctx.summary.add("multires_ndtom_derived_cells_n_mismatch", om.count_mismatches);
  drawByHeight(ctx, maps.ndtom, "multires_fine.png");
  drawByHeight(ctx, ndtom_coarse, "multires_coarse.png");
}

}  // namespace ndtom::eval
