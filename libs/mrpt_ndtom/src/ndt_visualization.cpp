#include "mrpt_ndtom/ndt_visualization.h"

#include <mrpt/opengl/CPointCloudColoured.h>
#include <mrpt/opengl/CSetOfTriangles.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <array>
#include <cmath>

#include "ndtom/map/map_queries.h"

namespace mrpt_ndtom {
namespace {

using Eigen::Vector3d;
using UnitTriangle = std::array<Vector3d, 3>;

// Octahedron refined `levels` times by splitting each triangle in four and pushing the new
// vertices onto the sphere.
std::vector<UnitTriangle> unitSphere(uint32_t levels) {
  const Vector3d x = Vector3d::UnitX(), y = Vector3d::UnitY(), z = Vector3d::UnitZ();
  std::vector<UnitTriangle> tris;
  for (const double sx : {1.0, -1.0})
    for (const double sy : {1.0, -1.0})
      for (const double sz : {1.0, -1.0}) {
        UnitTriangle t{sx * x, sy * y, sz * z};
        if (sx * sy * sz < 0) std::swap(t[1], t[2]);  // counter-clockwise seen from outside
        tris.push_back(t);
      }
  for (uint32_t level = 0; level < levels; ++level) {
    std::vector<UnitTriangle> finer;
    for (const auto& t : tris) {
      const Vector3d a = (t[0] + t[1]).normalized(), b = (t[1] + t[2]).normalized(),
                     c = (t[2] + t[0]).normalized();
      finer.insert(finer.end(), {{t[0], a, c}, {a, t[1], b}, {c, b, t[2]}, {a, b, c}});
    }
    tris.swap(finer);
  }
  return tris;
}

// Gaussians of occupied cells, the best-supported `max` of them, in cell order.
std::vector<ndtom::Gaussian> selectGaussians(const ndtom::NdtMap& map, const TRenderOptions& o) {
  std::vector<ndtom::Gaussian> all;
  map.forEachCellOrdered([&](const ndtom::CellView& c) {
    // A map without occupancy (Recursive NDT) has no log-odds to threshold.
    if (ndtom::isOccupiedGaussian(map, c) &&
        (!map.options().occupancy.enabled || c.logodds > o.min_logodds))
      all.push_back(map.gaussianOf(c, ndtom::Covariance::Regularized));
  });
  const size_t most = std::min<size_t>(o.max_ellipsoids, kMaxSceneTriangles / 8);
  if (all.size() > most) {
    std::stable_sort(all.begin(), all.end(),
                     [](const auto& a, const auto& b) { return a.n > b.n; });
    all.resize(most);
    std::sort(all.begin(), all.end(), [](const auto& a, const auto& b) { return a.cell < b.cell; });
  }
  return all;
}

std::pair<double, double> colorRange(const std::vector<ndtom::Gaussian>& gs,
                                     const TRenderOptions& o) {
  double lo = o.color_min_z, hi = o.color_max_z;
  if ((std::isnan(lo) || std::isnan(hi)) && !gs.empty()) {
    std::vector<double> z;
    for (const auto& g : gs) z.push_back(g.mean.z());
    const size_t i_lo = z.size() / 50, i_hi = z.size() - 1 - z.size() / 50;
    std::nth_element(z.begin(), z.begin() + i_lo, z.end());
    if (std::isnan(lo)) lo = z[i_lo];
    std::nth_element(z.begin(), z.begin() + i_hi, z.end());
    if (std::isnan(hi)) hi = z[i_hi];
  }
  if (!(hi > lo)) hi = lo + 1.0;
  return {lo, hi};
}

mrpt::math::TPoint3Df toFloat(const Vector3d& v) {
  return {float(v.x()), float(v.y()), float(v.z())};
}

void ellipsoidTriangles(const ndtom::Gaussian& g, const std::vector<UnitTriangle>& sphere,
                        double quantiles, const mrpt::img::TColor& color,
                        std::vector<mrpt::opengl::TTriangle>& out) {
  out.clear();
  // Surface point μ + A·u with A = V·diag(k·√λ); its normal is A⁻ᵀ·u.
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(g.covariance);
  const Vector3d sigma = eig.eigenvalues().cwiseMax(0.0).cwiseSqrt() * quantiles;
  const Eigen::Matrix3d a = eig.eigenvectors() * sigma.asDiagonal();
  const Eigen::Matrix3d normal_map =
      eig.eigenvectors() * sigma.cwiseMax(1e-9).cwiseInverse().asDiagonal();
  for (const auto& t : sphere) {
    mrpt::opengl::TTriangle tri;
    for (int k = 0; k < 3; ++k) {
      auto& v = tri.vertices[k];
      v.xyzrgba.pt = toFloat(g.mean + a * t[k]);
      v.setColor(color);
      const Vector3d n = (normal_map * t[k]).normalized();
      v.normal = {float(n.x()), float(n.y()), float(n.z())};
    }
    out.push_back(tri);
  }
}

mrpt::opengl::CPointCloudColoured::Ptr freeCells(const ndtom::NdtMap& map,
                                                 const TRenderOptions& o) {
  std::vector<Vector3d> centres;
  map.forEachCellOrdered([&](const ndtom::CellView& c) {
    if (ndtom::cellState(map, c) == ndtom::CellState::Free)
      centres.push_back(map.geometry().cellCenter(c.index));
  });
  auto cloud = mrpt::opengl::CPointCloudColoured::Create();
  cloud->setName("ndtom_free_cells");
  cloud->setPointSize(o.free_cell_point_size);
  if (o.max_free_cells == 0) return cloud;
  const size_t step =
      std::max<size_t>(1, (centres.size() + o.max_free_cells - 1) / o.max_free_cells);
  for (size_t i = 0; i < centres.size(); i += step) {
    const auto& p = centres[i];
    cloud->push_back(float(p.x()), float(p.y()), float(p.z()), 0.6f, 0.8f, 1.0f, 0.5f);
  }
  return cloud;
}

}  // namespace

size_t trianglesPerEllipsoid(uint32_t subdivisions) {
  return size_t(8) << (2 * subdivisions);
}

uint32_t subdivisionsWithinBudget(size_t drawn, uint32_t requested) {
  uint32_t s = requested;
  while (s > 0 && drawn * trianglesPerEllipsoid(s) > kMaxSceneTriangles) --s;
  return s;
}

std::vector<DrawnGaussian> drawnGaussians(const ndtom::NdtMap& map, const TRenderOptions& o) {
  o.validate();
  const std::vector<ndtom::Gaussian> gaussians = selectGaussians(map, o);
  const auto [z_lo, z_hi] = colorRange(gaussians, o);
  std::vector<DrawnGaussian> drawn;
  drawn.reserve(gaussians.size());
  for (const auto& g : gaussians) {
    float r, gr, b;
    const double t = std::clamp((g.mean.z() - z_lo) / (z_hi - z_lo), 0.0, 1.0);
    mrpt::img::colormap(o.colormap, float(t), r, gr, b);
    drawn.push_back({g, mrpt::img::TColor(uint8_t(255 * r), uint8_t(255 * gr), uint8_t(255 * b))});
  }
  return drawn;
}

void buildNdtVisualization(const ndtom::NdtMap& map, const TRenderOptions& o,
                           mrpt::opengl::CSetOfObjects& out) {
  buildNdtVisualization(map, drawnGaussians(map, o), o, out);
}

void buildNdtVisualization(const ndtom::NdtMap& map, const std::vector<DrawnGaussian>& drawn,
                           const TRenderOptions& o, mrpt::opengl::CSetOfObjects& out) {
  o.validate();
  if (!drawn.empty()) {
    // Gaussians selected elsewhere may be more than the budget draws: the first of them.
    const size_t count = std::min(drawn.size(), kMaxSceneTriangles / 8);
    const auto sphere = unitSphere(subdivisionsWithinBudget(count, o.subdivisions));
    // Straight into the mesh, one ellipsoid at a time: no second copy of every triangle.
    auto mesh = mrpt::opengl::CSetOfTriangles::Create();
    mesh->setName("ndtom_gaussians");
    mesh->reserve(count * sphere.size());
    std::vector<mrpt::opengl::TTriangle> tris;
    for (size_t i = 0; i < count; ++i) {
      const DrawnGaussian& d = drawn[i];
      ellipsoidTriangles(d.gaussian, sphere, o.quantiles, d.color, tris);
      mesh->insertTriangles(tris.begin(), tris.end());
    }
    out.insert(mesh);
  }
  if (o.show_free_cells) out.insert(freeCells(map, o));
}

}  // namespace mrpt_ndtom
