// Paper Sec. IV-A: Fig. 1 (consistency with the batch map) and Fig. 2 (representation
// self-test) for Error Refinement, Recursive NDT and NDT-OM.
#include "experiments.h"
#include "method_colors.h"
#include "ndtom_apps/progress.h"
#include "ndtom_eval/batch_ndt.h"
#include "ndtom_eval/error_refinement.h"

namespace ndtom::eval {

namespace {

struct ConsistencyMaps {
  NdtMap recursive, ndtom;
  ErrorRefinementMap er;
  ConsistencyMaps(const EvalOptions& options, double resolution)
      : recursive(recursiveNdtOptions(options, resolution)),
        ndtom(ndtOmOptions(options, resolution)),
        er([&] {
          ErrorRefinementOptions o;
          o.resolution = resolution;
          return o;
        }()) {}
};

// The figure's table and plot (one line per method, from the similarity_<method> columns),
// and one summary figure per method: `reduce` of its column under "<key><method>".
void writeFigure(EvalContext& ctx, const std::string& figure, const PlotAxes& axes,
                 const CsvTable& table, const std::string& key,
                 double (*reduce)(const std::vector<double>&)) {
  table.write(ctx.output(figure + ".csv"));
  const std::vector<double> x = table.column("cloud");
  writeLinePlot(ctx.output(figure + ".png"), axes,
                {{"Recursive NDT", x, table.column("similarity_recursive"), colors::kRecursive},
                 {"NDT-OM", x, table.column("similarity_ndtom"), colors::kNdtOm},
                 {"ER", x, table.column("similarity_er"), colors::kEr}});
  for (const char* method : {"recursive", "ndtom", "er"})
    ctx.summary.add(key + method, reduce(table.column(std::string("similarity_") + method)));
}

double last(const std::vector<double>& v) {
  return v.empty() ? 0.0 : v.back();
}

double mean(const std::vector<double>& v) {
  double sum = 0;
  for (double x : v) sum += x;
  return v.empty() ? 0.0 : sum / double(v.size());
}

// Fig. 1: insert one cloud at a time; after each, compare every map with the batch map.
void batchConsistency(EvalContext& ctx, const std::string& dataset,
                      const std::vector<Cloud>& clouds, ConsistencyMaps& maps) {
  const GridGeometry& geometry = maps.recursive.geometry();
  CsvTable table({"cloud", "points_so_far", "batch_gaussians", "recursive_gaussians",
                  "ndtom_gaussians", "er_gaussians", "similarity_recursive", "similarity_ndtom",
                  "similarity_er"});
  std::vector<Eigen::Vector3d> points_so_far;
  apps::Progress progress;
  progress.start("fig1 " + dataset, clouds.size());
  for (size_t i = 0; i < clouds.size(); ++i) {
    const Cloud& cloud = clouds[i];
    maps.recursive.insertScan(cloud.points, cloud.origin);
    maps.ndtom.insertScan(cloud.points, cloud.origin);
    maps.er.insertScan(cloud.points, cloud.origin);
    points_so_far.insert(points_so_far.end(), cloud.points.begin(), cloud.points.end());

    const GaussianSet batch = gaussianSetOf(batchNdt(points_so_far, geometry), geometry, ctx.floor);
    const GaussianSet recursive = gaussianSetOf(maps.recursive, ctx.floor);
    const GaussianSet ndtom = gaussianSetOf(maps.ndtom, ctx.floor);
    const GaussianSet er = gaussianSetOf(maps.er, ctx.floor);
    table.addRow({i + 1, points_so_far.size(), batch.size(), recursive.size(), ndtom.size(),
                  er.size(), mapSimilarity(recursive, batch), mapSimilarity(ndtom, batch),
                  mapSimilarity(er, batch)});
    progress.step();
  }
  PlotAxes axes{"Fig. 1 (" + dataset + "): each map vs the batch map", "clouds inserted",
                "mean L2 similarity to the batch map", 0.0, 1.02};
  writeFigure(ctx, "fig1_" + dataset, axes, table, "fig1_" + dataset + "_final_similarity_", last);
}

// Fig. 2: every single cloud's NDT against each map built from all clouds.
void selfTest(EvalContext& ctx, const std::string& dataset, const std::vector<Cloud>& clouds,
              const ConsistencyMaps& maps) {
  const GridGeometry& geometry = maps.recursive.geometry();
  const GaussianSet recursive = gaussianSetOf(maps.recursive, ctx.floor);
  const GaussianSet ndtom = gaussianSetOf(maps.ndtom, ctx.floor);
  const GaussianSet er = gaussianSetOf(maps.er, ctx.floor);
  CsvTable table(
      {"cloud", "cloud_gaussians", "similarity_recursive", "similarity_ndtom", "similarity_er"});
  apps::Progress progress;
  progress.start("fig2 " + dataset, clouds.size(), "clouds");
  for (size_t i = 0; i < clouds.size(); ++i) {
    const std::vector<Eigen::Vector3d>& points = clouds[i].points;
    const size_t own = gaussianSetOf(batchNdt(points, geometry), geometry, ctx.floor).size();
    table.addRow({i + 1, own, scanSimilarity(points, recursive, geometry, ctx.floor),
                  scanSimilarity(points, ndtom, geometry, ctx.floor),
                  scanSimilarity(points, er, geometry, ctx.floor)});
    progress.step();
  }
  PlotAxes axes{"Fig. 2 (" + dataset + "): each cloud vs the map of all clouds", "cloud",
                "mean L2 similarity of the cloud's NDT", 0.0, 1.02};
  writeFigure(ctx, "fig2_" + dataset, axes, table, "fig2_" + dataset + "_mean_similarity_", mean);
}

}  // namespace

void runConsistency(EvalContext& ctx, const std::string& dataset, const std::vector<Cloud>& clouds,
                    double resolution) {
  ConsistencyMaps maps(ctx.options, resolution);
  batchConsistency(ctx, dataset, clouds, maps);
  selfTest(ctx, dataset, clouds, maps);
}

}  // namespace ndtom::eval
