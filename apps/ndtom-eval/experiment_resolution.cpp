// Map quality against resolution: each map's similarity to the batch map of the same points,
// its memory (NdtMap::memoryBytes) and its insertion time per scan (ER: similarity only).
#include "experiments.h"
#include "method_colors.h"
#include "ndtom_apps/progress.h"
#include "ndtom_eval/batch_ndt.h"
#include "ndtom_eval/error_refinement.h"

namespace ndtom::eval {

namespace {

struct BuiltMap {
  NdtMap map;
  double seconds = 0;  ///< total insertion time
};

BuiltMap build(const MapOptions& options, const std::vector<Cloud>& clouds) {
  BuiltMap built{NdtMap(options)};
  for (const Cloud& c : clouds)
    built.seconds += timed([&] { built.map.insertScan(c.points, c.origin); });
  return built;
}

double erSimilarity(const EvalContext& ctx, double resolution, const std::vector<Cloud>& clouds,
                    const GaussianSet& batch) {
  ErrorRefinementOptions options;
  options.resolution = resolution;
  ErrorRefinementMap er(options);
  for (const Cloud& c : clouds) er.insertScan(c.points, c.origin);
  return mapSimilarity(gaussianSetOf(er, ctx.floor), batch);
}

void plotSweep(EvalContext& ctx, const CsvTable& table) {
  const std::vector<double> x = table.column("resolution");
  PlotAxes quality{"Similarity to the batch map vs resolution (lidar, all scans)", "resolution (m)",
                   "mean L2 similarity to the batch map", 0.0, 1.02};
  writeLinePlot(ctx.output("sweep_similarity.png"), quality,
                {{"Recursive NDT", x, table.column("similarity_recursive"), colors::kRecursive},
                 {"NDT-OM", x, table.column("similarity_ndtom"), colors::kNdtOm},
                 {"ER", x, table.column("similarity_er"), colors::kEr}});
  std::vector<double> rec_mb, om_mb;
  for (double b : table.column("memory_recursive_bytes")) rec_mb.push_back(b / 1e6);
  for (double b : table.column("memory_ndtom_bytes")) om_mb.push_back(b / 1e6);
  PlotAxes memory{"Map memory vs resolution (NdtMap::memoryBytes)", "resolution (m)",
                  "memory (MB, log scale)"};
  memory.log_y = true;
  writeLinePlot(
      ctx.output("sweep_memory.png"), memory,
      {{"Recursive NDT", x, rec_mb, colors::kRecursive}, {"NDT-OM", x, om_mb, colors::kNdtOm}});
}

}  // namespace

void runResolutionSweep(EvalContext& ctx, const std::vector<Cloud>& clouds) {
  const std::vector<Eigen::Vector3d> points = allPoints(clouds);
  CsvTable table({"resolution", "batch_gaussians", "recursive_gaussians", "ndtom_gaussians",
                  "similarity_recursive", "similarity_ndtom", "similarity_er",
                  "memory_recursive_bytes", "memory_ndtom_bytes", "ms_per_scan_recursive",
                  "ms_per_scan_ndtom"});
  apps::Progress progress;
  progress.start("sweep", ctx.options.sweep_resolutions.size(), "resolutions");
  for (double resolution : ctx.options.sweep_resolutions) {
    const BuiltMap recursive = build(recursiveNdtOptions(ctx.options, resolution), clouds);
    const BuiltMap ndtom = build(ndtOmOptions(ctx.options, resolution), clouds);
    const GridGeometry& geometry = recursive.map.geometry();
    const GaussianSet batch = gaussianSetOf(batchNdt(points, geometry), geometry, ctx.floor);
    const double scans = double(clouds.size());
    table.addRow({resolution, batch.size(), recursive.map.numGaussians(), ndtom.map.numGaussians(),
                  mapSimilarity(gaussianSetOf(recursive.map, ctx.floor), batch),
                  mapSimilarity(gaussianSetOf(ndtom.map, ctx.floor), batch),
                  erSimilarity(ctx, resolution, clouds, batch), recursive.map.memoryBytes(),
                  ndtom.map.memoryBytes(), 1e3 * recursive.seconds / scans,
                  1e3 * ndtom.seconds / scans});
    progress.step();
  }
  table.write(ctx.output("sweep.csv"));
  plotSweep(ctx, table);
}

}  // namespace ndtom::eval
