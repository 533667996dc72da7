// RayMode::PerHitCell (one weighted ray per hit cell) against the reference RayMode::PerPoint
// (one ray per point, the paper's Eq. 12): how close the maps are, and what it saves.
#include <algorithm>
#include <unordered_map>

#include "experiments.h"
#include "ndtom_apps/progress.h"

namespace ndtom::eval {

namespace {

struct ModeRun {
  NdtMap map;
  double seconds = 0;
  size_t voxel_visits = 0;
};

ModeRun build(const EvalOptions& options, double resolution, RayMode mode,
              const std::vector<Cloud>& clouds) {
  ModeRun run{NdtMap(ndtOmOptions(options, resolution, mode))};
  for (const Cloud& c : clouds) {
    InsertionReport report;
    run.seconds += timed([&] { report = run.map.insertScan(c.points, c.origin); });
    run.voxel_visits += report.voxel_visits;
  }
  return run;
}

int sign(float v) {
  return (v > 0.f) - (v < 0.f);
}

/// Share of the cells known to either map whose occupancy sign differs (unknown counts as 0).
double signDisagreement(const NdtMap& a, const NdtMap& b) {
  std::unordered_map<CellIndex, std::pair<int, int>, CellIndexHash> signs;  // (a, b)
  a.forEachCell([&](const CellView& c) { signs[c.index].first = sign(c.logodds); });
  b.forEachCell([&](const CellView& c) { signs[c.index].second = sign(c.logodds); });
  const size_t differ = size_t(std::count_if(signs.begin(), signs.end(), [](const auto& entry) {
    return entry.second.first != entry.second.second;
  }));
  return signs.empty() ? 0.0 : double(differ) / double(signs.size());
}

}  // namespace

void runRayModes(EvalContext& ctx, const std::vector<Cloud>& clouds) {
  CsvTable table({"resolution", "gaussians_per_point", "gaussians_per_hit_cell",
                  "similarity_hit_cell_vs_per_point", "similarity_per_point_vs_hit_cell",
                  "occupancy_sign_differs_share", "voxel_visits_per_point",
                  "voxel_visits_per_hit_cell", "visits_ratio", "ms_per_scan_per_point",
                  "ms_per_scan_per_hit_cell", "time_ratio"});
  apps::Progress progress;
  progress.start("raymodes", ctx.options.ray_mode_resolutions.size(), "resolutions");
  for (double resolution : ctx.options.ray_mode_resolutions) {
    const ModeRun per_point = build(ctx.options, resolution, RayMode::PerPoint, clouds);
    const ModeRun hit_cell = build(ctx.options, resolution, RayMode::PerHitCell, clouds);
    const GaussianSet ref = gaussianSetOf(per_point.map, ctx.floor);
    const GaussianSet test = gaussianSetOf(hit_cell.map, ctx.floor);
    const double scans = double(clouds.size());
    table.addRow(
        {resolution, ref.size(), test.size(), mapSimilarity(test, ref), mapSimilarity(ref, test),
         signDisagreement(per_point.map, hit_cell.map), per_point.voxel_visits,
         hit_cell.voxel_visits,
         double(hit_cell.voxel_visits) / double(std::max<size_t>(1, per_point.voxel_visits)),
         1e3 * per_point.seconds / scans, 1e3 * hit_cell.seconds / scans,
         hit_cell.seconds / std::max(1e-12, per_point.seconds)});
    progress.step();
  }
  table.write(ctx.output("raymodes.csv"));
}

}  // namespace ndtom::eval
