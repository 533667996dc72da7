// Paper Fig. 4 a-d as 3D pictures of the lidar map at the mapping resolution, rendered
// headless (oblique_render.h): a) NDT-OM, b) Recursive NDT with the conflicting cells,
// c) the cells NDT-OM estimates empty, up to 1.5 m above the ground, d) the coarse map derived
// from a). Shown: the part within kRadius of the middle of the sensor path.
#include <algorithm>
#include <cstdio>
#include <unordered_set>

#include "experiments.h"
#include "ndtom/map/map_queries.h"
#include "oblique_render.h"
#include "top_view.h"

namespace ndtom::eval {

namespace {

constexpr double kRadius = 25;       // m, horizontally around the middle of the path
constexpr double kAzimuth = -60;     // degrees: the camera sits south-east of the scene
constexpr double kElevation = 40;    // degrees above the horizon
constexpr double kFreeHeight = 1.5;  // m above the ground, as the paper's Fig. 4c
const cv::Scalar kGrey = cv::Scalar::all(190), kRed{30, 30, 220}, kPath{200, 90, 30};

struct Scene {
  Eigen::Vector3d centre;
  double ground_z, z_lo, z_hi;  ///< ground estimate; colour range of the heights
  bool near(const Eigen::Vector3d& p) const { return (p - centre).head<2>().norm() <= kRadius; }
  double colourOf(const Eigen::Vector3d& p) const {
    return std::clamp((p.z() - z_lo) / (z_hi - z_lo), 0.0, 1.0);
  }
};

double percentile(std::vector<double> v, double q) {
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, size_t(q * double(v.size())))];
}

std::vector<Gaussian> occupiedGaussians(const NdtMap& map, const Scene& scene) {
  std::vector<Gaussian> out;
  map.forEachCell([&](const CellView& c) {
    if (!isOccupiedGaussian(map, c)) return;
    const Gaussian g = map.gaussianOf(c);
    if (scene.near(g.mean)) out.push_back(g);
  });
  return out;
}

std::vector<Eigen::Vector3d> meansOf(const std::vector<Gaussian>& gaussians) {
  std::vector<Eigen::Vector3d> means;
  for (const Gaussian& g : gaussians) means.push_back(g.mean);
  return means;
}

ObliqueRender view(const std::vector<Eigen::Vector3d>& extent) {
  return ObliqueRender(extent, kAzimuth, kElevation);
}

void drawByHeight(EvalContext& ctx, const NdtMap& map, const Scene& scene,
                  const std::vector<Eigen::Vector3d>& extent,
                  const std::vector<Eigen::Vector3d>& path, const std::string& file,
                  const std::string& title) {
  const std::vector<Gaussian> gaussians = occupiedGaussians(map, scene);
  ObliqueRender r = view(extent);
  for (const Gaussian& g : gaussians) r.addGaussian(g, viridis(scene.colourOf(g.mean)));
  r.setPath(path, kPath);
  char legend[120];
  std::snprintf(legend, sizeof legend, "%zu occupied Gaussians (1-sigma ellipsoids), by height",
                gaussians.size());
  const std::pair<double, double> bar{scene.z_lo, scene.z_hi};
  r.write(ctx.output(file), title, {{legend, viridis(0.5)}, {"sensor path", kPath}}, &bar);
}

}  // namespace

void runFig4(EvalContext& ctx, const MappingMaps& maps) {
  Scene scene;
  scene.centre = maps.path[maps.path.size() / 2];
  const std::vector<Gaussian> fine = occupiedGaussians(maps.ndtom, scene);
  if (fine.empty()) return;
  std::vector<double> z;
  for (const Gaussian& g : fine) z.push_back(g.mean.z());
  // The 5th percentile of the heights stands for the ground: most Gaussians lie on it.
  scene.ground_z = percentile(z, 0.05);
  scene.z_lo = percentile(z, 0.02);
  scene.z_hi = std::max(percentile(z, 0.98), scene.z_lo + 0.1);
  const std::vector<Eigen::Vector3d> extent = meansOf(fine);  // the same framing for a-d
  const double res = maps.ndtom.geometry().resolution();
  char title[160];

  std::snprintf(title, sizeof title, "Fig. 4a: NDT-OM, %.2f m, lidar (%.0f m around the path)", res,
                kRadius);
  drawByHeight(ctx, maps.ndtom, scene, extent, maps.path, "fig4a_ndtom.png", title);

  // b) Recursive NDT, the conflicting cells (Gaussian here, empty in NDT-OM) in red.
  const std::vector<CellIndex> conflict_list = dynamicConflicts(maps);
  const std::unordered_set<CellIndex, CellIndexHash> conflicts(conflict_list.begin(),
                                                               conflict_list.end());
  ObliqueRender b = view(extent);
  size_t shown = 0, shown_conflicts = 0;
  maps.recursive.forEachCell([&](const CellView& c) {
    if (!c.stats || !c.stats->hasGaussian()) return;
    const Gaussian g = maps.recursive.gaussianOf(c);
    if (!scene.near(g.mean)) return;
    ++shown;
    const bool conflict = conflicts.count(c.index) > 0;
    shown_conflicts += conflict;
    b.addGaussian(g, conflict ? kRed : kGrey);
  });
  b.setPath(maps.path, kPath);
  char l1[120], l2[120];
  std::snprintf(l1, sizeof l1, "%zu Recursive NDT Gaussians", shown - shown_conflicts);
  std::snprintf(l2, sizeof l2, "%zu conflicts: Gaussian in Recursive NDT, empty in NDT-OM",
                shown_conflicts);
  std::snprintf(title, sizeof title, "Fig. 4b: Recursive NDT (no occupancy), %.2f m", res);
  b.write(ctx.output("fig4b_recursive_conflicts.png"), title,
          {{l1, kGrey}, {l2, kRed}, {"sensor path", kPath}});

  // c) Free cells (log-odds < 0) up to kFreeHeight above the ground, as spheres.
  ObliqueRender c = view(extent);
  size_t free_shown = 0;
  maps.ndtom.forEachCell([&](const CellView& cell) {
    if (cellState(maps.ndtom, cell) != CellState::Free) return;
    const Eigen::Vector3d centre = maps.ndtom.geometry().cellCenter(cell.index);
    if (!scene.near(centre) || centre.z() > scene.ground_z + kFreeHeight) return;
    ++free_shown;
    const cv::Scalar colour = viridis((centre.z() - scene.ground_z) / kFreeHeight);
    c.addSphere(centre, 0.3 * res, colour, colour * 0.6);
  });
  c.setPath(maps.path, kPath);
  char l3[160];
  std::snprintf(l3, sizeof l3,
                "%zu empty cells (log-odds < 0) as spheres, centres up to %.1f m above z %.1f",
                free_shown, kFreeHeight, scene.ground_z);
  std::snprintf(title, sizeof title, "Fig. 4c: cells NDT-OM estimates empty, %.2f m", res);
  const std::pair<double, double> free_bar{scene.ground_z, scene.ground_z + kFreeHeight};
  c.write(ctx.output("fig4c_free.png"), title, {{l3, viridis(0.5)}, {"sensor path", kPath}},
          &free_bar);
  ctx.summary.add("fig4c_free_cells_shown", free_shown);
  ctx.summary.add("fig4_ground_z", scene.ground_z);

  // d) The coarse map derived from a).
  const NdtMap coarse = maps.ndtom.coarsened(ctx.options.coarsening);
  std::snprintf(title, sizeof title, "Fig. 4d: NDT-OM %.2f m derived from 4a (RCU)",
                coarse.geometry().resolution());
  drawByHeight(ctx, coarse, scene, extent, maps.path, "fig4d_coarse.png", title);
}

}  // namespace ndtom::eval
