#include "targets.h"

#include <algorithm>
#include <cstdio>

#include "report.h"

namespace ndtom::bench {

namespace {

std::string verdict(bool pass) {
  return pass ? "PASS " : "FAIL ";
}

std::string printf1(const char* fmt, double a, double b = 0, double c = 0) {
  char buf[320];
  std::snprintf(buf, sizeof buf, fmt, a, b, c);
  return buf;
}

std::vector<const RunResult*> runsOf(const std::vector<RunResult>& runs, const std::string& ds) {
  std::vector<const RunResult*> out;
  for (const RunResult& r : runs)
    if (r.dataset == ds) out.push_back(&r);
  return out;
}

std::string speedTarget(const std::vector<RunResult>& runs, const std::string& ds) {
  const std::string name = "time at 0.2 m <= 0.1 x OctoMap and <= 1.5 x COccupancyGridMap3D";
  std::string detail, passing;
  for (const char* mode : {"ndtom-point/t1", "ndtom-hitcell/t1"}) {
    const RunResult* r = findRun(runs, ds, kTargetResolution, mode);
    if (!r) continue;
    const auto o = timeRatio(runs, *r, "octomap", true);
    const auto g = timeRatio(runs, *r, "mrpt-grid3d", true);
    if (!o || !g) return "SKIP " + name + ": needs octomap and mrpt-grid3d at 0.2 m";
    const auto o_wall = timeRatio(runs, *r, "octomap"), g_wall = timeRatio(runs, *r, "mrpt-grid3d");
    detail += std::string(detail.empty() ? "" : "; ") + mode +
              printf1(" %.2f CPU ms/scan = %.3f x OctoMap, %.2f x grid",
                      r->medianCpuSeconds() * 1e3, *o, *g) +
              printf1(" (wall: %.3f x, %.2f x)", o_wall.value_or(0), g_wall.value_or(0));
    if (*o <= kMaxTimeVsOctomap && *g <= kMaxTimeVsGrid3d)
      passing += std::string(passing.empty() ? "" : ", ") + mode;
  }
  if (detail.empty()) return "SKIP " + name + ": no single-thread NDT-OM run at 0.2 m";
  return verdict(!passing.empty()) + name + ": " + detail +
         (passing.empty() ? "" : " (met by " + passing + ")");
}

std::string memoryTarget(const std::vector<const RunResult*>& runs) {
  const std::string name = "memory <= 64 B per touched cell (NdtMap::memoryBytes / numCells)";
  const RunResult* worst = nullptr;
  for (const RunResult* r : runs)
    if (isNdtom(r->kind) && (!worst || r->bytesPerCell() > worst->bytesPerCell())) worst = r;
  if (!worst) return "SKIP " + name + ": no NDT-OM run";
  std::string at_target;
  for (const RunResult* r : runs)
    if (r->label == "ndtom-point/t1" && r->resolution == kTargetResolution)
      at_target = printf1("; %.1f B/cell at 0.2 m", r->bytesPerCell());
  return verdict(worst->bytesPerCell() <= kMaxBytesPerCell) + name + ": worst " +
         printf1("%.1f B/cell", worst->bytesPerCell()) + " (" + worst->label +
         printf1(" at %.2f m)", worst->resolution) + at_target;
}

std::string threadTarget(const std::vector<RunResult>& runs,
                         const std::vector<const RunResult*>& ds_runs) {
  // Judged in the paper's per-point mode, where tracing dominates; per-hit-cell mode traces
  // a quarter of the cells, so its serial stages (sort, block allocation) weigh more. Its
  // speed-up is listed; its maps must be identical too.
  const std::string name =
      "2 threads >= 1.6 x one thread's rate (per-point mode), identical map (every mode)";
  std::string detail;
  bool pass = true, any = false;
  for (const RunResult* r : ds_runs) {
    if (!isNdtom(r->kind) || r->threads != 2 || !r->vs_one_thread) continue;
    const std::optional<double> separate = oneThreadSpeedup(runs, *r);
    if (!separate) continue;
    // Judged side by side (runPaired) when measured: separate runs can meet different loads.
    const double speedup = r->paired_speedup.value_or(*separate);
    pass &= r->vs_one_thread->identical;
    if (r->kind == SystemKind::NdtomPerPoint) pass &= speedup >= kMinTwoThreadSpeedup;
    any = true;
    detail += std::string(detail.empty() ? "" : "; ") + r->label +
              printf1(" %.2f m: %.2fx", r->resolution, speedup) +
              (r->paired_speedup ? printf1(" side by side (%.2fx in separate runs)", *separate)
                                 : std::string()) +
              (r->vs_one_thread->identical ? " identical" : " MAP DIFFERS");
  }
  if (!any) return "SKIP " + name + ": no 2-thread NDT-OM run (see --threads)";
  return verdict(pass) + name + ": " + detail;
}

std::string similarityTarget(const std::vector<const RunResult*>& runs) {
  const std::string name = "every speed-up keeps the map: similarity >= 0.99 to the exact path";
  std::string detail;
  bool pass = true, any = false, pending = false;
  for (const RunResult* r : runs) {
    if (!r->vs_exact) continue;
    any = true;
    const MapComparison& c = *r->vs_exact;
    if (c.similarity) {
      pass &= *c.similarity >= kMinSimilarity;
      detail += std::string(detail.empty() ? "" : "; ") + r->label +
                printf1(" %.2f m: %.4f", r->resolution, *c.similarity);
    } else {
      pending = true;
      detail += std::string(detail.empty() ? "" : "; ") + r->label +
                printf1(" %.2f m: Gaussians %+.2f %%, occupancy differs in %.2f %% of cells",
                        r->resolution,
                        100.0 * (double(c.gaussians_test) - double(c.gaussians_reference)) /
                            double(std::max<size_t>(1, c.gaussians_reference)),
                        100.0 * c.occupancy_mismatch);
    }
  }
  if (!any) return "SKIP " + name + ": needs ndtom-point/t1 and a faster variant";
  if (pending)
    return "SKIP " + name + ": the core has no similarity function yet; fallback: " + detail;
  return verdict(pass) + name + ": " + detail;
}

/// Single-thread runs that lost the core to other processes: wall time is inflated.
std::string noiseNote(const std::vector<const RunResult*>& runs) {
  double worst = 1;
  for (const RunResult* r : runs)
    if (r->threads == 1) worst = std::min(worst, r->cpuPerWall());
  if (worst >= kMinCpuPerWall) return "";
  return printf1(
      "NOTE the machine was busy: a single-thread run got only %.2f of a core (CPU/wall): "
      "wall-clock times and the thread target are unreliable, CPU times less so; re-run idle",
      worst);
}

}  // namespace

std::vector<std::string> checkTargets(const std::vector<RunResult>& runs,
                                      const std::string& dataset) {
  const std::vector<const RunResult*> ds_runs = runsOf(runs, dataset);
  std::vector<std::string> lines = {speedTarget(runs, dataset), memoryTarget(ds_runs),
                                    threadTarget(runs, ds_runs), similarityTarget(ds_runs)};
  if (std::string note = noiseNote(ds_runs); !note.empty()) lines.push_back(note);
  return lines;
}

}  // namespace ndtom::bench
