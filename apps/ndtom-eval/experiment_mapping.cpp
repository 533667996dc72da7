// Paper Sec. IV-B-2 on the lidar sequence: Fig. 3 (mean log-odds of occupied and of empty
// cells after every scan) and the "dynamic" conflicts: cells that hold a Gaussian in
// Recursive NDT but are empty in NDT-OM.
#include <algorithm>
#include <cmath>
#include <map>

#include "experiments.h"
#include "method_colors.h"
#include "ndtom/map/map_queries.h"
#include "ndtom_apps/progress.h"
#include "top_view.h"

namespace ndtom::eval {

namespace {

struct OccupancyStats {
  size_t known = 0, occupied = 0, empty = 0;
  double mean_occupied = 0, mean_empty = 0;  ///< mean log-odds; 0 when there are none
};

OccupancyStats occupancyStats(const NdtMap& map) {
  OccupancyStats s;
  double sum_occupied = 0, sum_empty = 0;
  map.forEachCell([&](const CellView& c) {
    ++s.known;
    const CellState state = cellState(map, c);
    if (state == CellState::Occupied) {
      ++s.occupied;
      sum_occupied += c.logodds;
    } else if (state == CellState::Free) {
      ++s.empty;
      sum_empty += c.logodds;
    }
  });
  if (s.occupied) s.mean_occupied = sum_occupied / double(s.occupied);
  if (s.empty) s.mean_empty = sum_empty / double(s.empty);
  return s;
}

void plotFig3(EvalContext& ctx, const CsvTable& table) {
  const std::vector<double> x = table.column("scan");
  PlotAxes axes{"Fig. 3: mean log-odds of occupied and empty cells (NDT-OM)", "scans inserted",
                "mean log-odds"};
  writeLinePlot(ctx.output("fig3_occupancy.png"), axes,
                {{"occupied (l > 0)", x, table.column("mean_logodds_occupied"), colors::kNdtOm},
                 {"empty (l < 0)", x, table.column("mean_logodds_empty"), colors::kEr}});
}

double medianPoints(const NdtMap& map, const std::vector<CellIndex>& cells) {
  std::vector<uint32_t> n;
  for (const CellIndex& c : cells) n.push_back(map.cell(c)->stats->n);
  if (n.empty()) return 0.0;
  std::nth_element(n.begin(), n.begin() + long(n.size() / 2), n.end());
  return n[n.size() / 2];
}

// Where the conflicts are: per 1 m band of height above the first sensor position.
void writeConflictsByHeight(EvalContext& ctx, const MappingMaps& maps,
                            const std::vector<CellIndex>& conflicts) {
  const double sensor_z = maps.path.front().z();
  std::map<int, std::pair<size_t, size_t>> bands;  // band -> (Gaussians, conflicts)
  auto band = [&](const Eigen::Vector3d& p) { return int(std::floor(p.z() - sensor_z)); };
  maps.recursive.forEachGaussian([&](const Gaussian& g) { ++bands[band(g.mean)].first; },
                                 Covariance::Exact);
  for (const CellIndex& c : conflicts)
    ++bands[band(maps.recursive.gaussian(c, Covariance::Exact)->mean)].second;
  CsvTable table({"height_above_sensor_min_m", "height_above_sensor_max_m", "recursive_gaussians",
                  "conflicts", "conflict_share"});
  for (const auto& [b, counts] : bands)
    table.addRow({b, b + 1, counts.first, counts.second,
                  double(counts.second) / double(std::max<size_t>(1, counts.first))});
  table.write(ctx.output("conflicts_by_height.csv"));
}

void drawConflicts(EvalContext& ctx, const MappingMaps& maps,
                   const std::vector<CellIndex>& conflicts) {
  std::vector<Gaussian> gaussians, conflicting;
  std::vector<Eigen::Vector3d> extent = maps.path;
  maps.recursive.forEachGaussian([&](const Gaussian& g) {
    gaussians.push_back(g);
    extent.push_back(g.mean);
  });
  if (gaussians.empty()) return;
  for (const CellIndex& c : conflicts) conflicting.push_back(*maps.recursive.gaussian(c));
  // Heights relative to the first sensor position, in the bands of conflicts_by_height.csv.
  const double sensor_z = maps.path.front().z(), z_lo = sensor_z - 3, z_hi = sensor_z + 9;
  TopView view(extent);
  view.drawGaussians(gaussians, cv::Scalar::all(205));
  // The conflicting Gaussians themselves (not their cells' squares), coloured by height.
  view.drawGaussiansByHeight(conflicting, z_lo, z_hi);
  view.drawPath(maps.path, {200, 90, 30});
  char conflict_line[120];
  std::snprintf(conflict_line, sizeof conflict_line,
                "%zu conflicts: Gaussian in Recursive NDT, empty in NDT-OM (colour: height)",
                conflicting.size());
  view.drawLegend({{"Gaussian in Recursive NDT (1-sigma, top view)", cv::Scalar::all(205)},
                   {conflict_line, viridis(0.5)},
                   {"sensor path", {200, 90, 30}}});
  view.drawHeightBar(z_lo, z_hi);
  view.write(ctx.output("conflicts_top.png"));
}

void reportConflicts(EvalContext& ctx, const MappingMaps& maps) {
  const std::vector<CellIndex> conflicts = dynamicConflicts(maps);
  const size_t ndtom_gaussians = maps.ndtom.numGaussians();
  ctx.summary.add("conflicts_count", conflicts.size());
  ctx.summary.add("conflicts_recursive_gaussians", maps.recursive.numGaussians());
  ctx.summary.add("conflicts_ndtom_gaussians", ndtom_gaussians);
  ctx.summary.add("conflicts_ndtom_known_cells", maps.ndtom.numCells());
  ctx.summary.add("conflicts_share_of_ndtom_gaussians",
                  double(conflicts.size()) / double(std::max<size_t>(1, ndtom_gaussians)));
  ctx.summary.add("conflicts_share_of_ndtom_known_cells",
                  double(conflicts.size()) / double(std::max<size_t>(1, maps.ndtom.numCells())));
  std::vector<CellIndex> all_gaussians;
  maps.recursive.forEachCell([&](const CellView& c) {
    if (c.stats && c.stats->hasGaussian()) all_gaussians.push_back(c.index);
  });
  ctx.summary.add("conflicts_median_points_per_conflict_cell",
                  medianPoints(maps.recursive, conflicts));
  ctx.summary.add("conflicts_median_points_per_recursive_gaussian",
                  medianPoints(maps.recursive, all_gaussians));
  writeConflictsByHeight(ctx, maps, conflicts);
  drawConflicts(ctx, maps, conflicts);
}

}  // namespace

// Observed empty in NDT-OM: it dropped or never kept a Gaussian there.
std::vector<CellIndex> dynamicConflicts(const MappingMaps& maps) {
  std::vector<CellIndex> conflicts;
  maps.recursive.forEachCell([&](const CellView& c) {
    if (!c.stats || !c.stats->hasGaussian()) return;
    const auto other = maps.ndtom.cell(c.index);
    if (other && cellState(maps.ndtom, *other) != CellState::Occupied) conflicts.push_back(c.index);
  });
  return conflicts;
}

MappingMaps runMapping(EvalContext& ctx, const std::vector<Cloud>& clouds, bool record) {
  const double resolution = ctx.options.mapping_resolution;
  MappingMaps maps{NdtMap(recursiveNdtOptions(ctx.options, resolution)),
                   NdtMap(ndtOmOptions(ctx.options, resolution)),
                   {}};
  CsvTable table({"scan", "known_cells", "occupied_cells", "empty_cells", "mean_logodds_occupied",
                  "mean_logodds_empty", "ndtom_gaussians", "recursive_gaussians"});
  apps::Progress progress;
  progress.start("mapping", clouds.size());
  for (size_t i = 0; i < clouds.size(); ++i) {
    maps.recursive.insertScan(clouds[i].points, clouds[i].origin);
    maps.ndtom.insertScan(clouds[i].points, clouds[i].origin);
    maps.path.push_back(clouds[i].origin);
    if (record) {
      const OccupancyStats s = occupancyStats(maps.ndtom);
      table.addRow({i + 1, s.known, s.occupied, s.empty, s.mean_occupied, s.mean_empty,
                    maps.ndtom.numGaussians(), maps.recursive.numGaussians()});
    }
    progress.step();
  }
  if (!record) return maps;
  table.write(ctx.output("fig3_occupancy.csv"));
  plotFig3(ctx, table);
  ctx.summary.add("fig3_final_mean_logodds_occupied", table.column("mean_logodds_occupied").back());
  ctx.summary.add("fig3_final_mean_logodds_empty", table.column("mean_logodds_empty").back());
  reportConflicts(ctx, maps);
  return maps;
}

}  // namespace ndtom::eval
