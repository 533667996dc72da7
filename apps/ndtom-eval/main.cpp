// ndtom-eval: reproduces the evaluation of Saarinen et al. 2013 (Sec. IV) on real data and
// writes its CSV tables and PNG plots. See doc/evaluation.md for the results.
#include <cstdio>
#include <filesystem>

#include "experiments.h"
#include "ndtom_apps/run_program.h"

using namespace ndtom::eval;

namespace {

void runAll(EvalContext& ctx) {
  const EvalOptions& o = ctx.options;
  if (o.runsConsistencyOn("tum")) {
    const auto tum = loadTumClouds(o.tum_dir, o.tum_frames, o.tum_decimation);
    std::fprintf(stderr, "TUM: %zu frames, %zu points (decimation %d)\n", tum.size(),
                 totalPoints(tum), o.tum_decimation);
    ctx.summary.add("tum_frames", tum.size());
    ctx.summary.add("tum_points", totalPoints(tum));
    runConsistency(ctx, "tum", tum, o.tum_resolution);
  }
  const bool needs_lidar = o.runsConsistencyOn("lidar") || o.runs("mapping") ||
                           o.runs("multires") || o.runs("sweep") || o.runs("raymodes") ||
                           o.runs("fig4");
  if (!needs_lidar) return;
  size_t lidar_available = 0;
  const auto lidar = loadLidarClouds(o.lidar_dir, o.lidar_scans, o.motion, &lidar_available);
  std::fprintf(stderr, "lidar: %zu of %zu scans (insertion rule %s), %zu points\n", lidar.size(),
               lidar_available, o.motion.enabled() ? "on" : "off", totalPoints(lidar));
  ctx.summary.add("lidar_scans_read", lidar_available);
  ctx.summary.add("lidar_min_travel_m", o.motion.min_travel);
  ctx.summary.add("lidar_min_turn_deg", o.motion.min_turn_deg);
  ctx.summary.add("lidar_scans", lidar.size());
  ctx.summary.add("lidar_points", totalPoints(lidar));
  if (o.runsConsistencyOn("lidar")) {
    const size_t n = std::min(lidar.size(), size_t(o.consistency_scans));
    runConsistency(ctx, "lidar", {lidar.begin(), lidar.begin() + long(n)}, o.lidar_resolution);
  }
  if (o.runs("mapping") || o.runs("multires") || o.runs("fig4")) {
    const MappingMaps maps = runMapping(ctx, lidar, o.runs("mapping"));
    if (o.runs("multires")) runMultiResolution(ctx, lidar, maps);
    if (o.runs("fig4")) runFig4(ctx, maps);
  }
  if (o.runs("sweep")) runResolutionSweep(ctx, lidar);
  if (o.runs("raymodes")) runRayModes(ctx, lidar);
}

int run(const EvalOptions& options) {
  std::filesystem::create_directories(options.out_dir);
  Summary summary;
  summary.add("clamp_min", options.clamp_min);
  summary.add("clamp_max", options.clamp_max);
  EvalContext ctx{options, summary, ndtom::CovarianceFloor{options.min_eigenvalue}, {}};
  runAll(ctx);
  summary.write(ctx.output("summary.csv"));
  summary.print();
  std::printf("\nWrote %zu files to %s\n", ctx.files_written.size(), options.out_dir.c_str());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  return ndtom::apps::runProgram("ndtom-eval", [&] {
    const EvalOptions options = parseEvalOptions(argc, argv);
    if (options.help) {
      std::fputs(helpText().c_str(), stdout);
      return 0;
    }
    return run(options);
  });
}
