#include "ndtom_apps/depth_canvas.h"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <limits>

namespace ndtom::apps {
namespace {

constexpr double kAmbient = 0.35, kDiffuse = 0.65;

struct PixelBox {
  int x0, y0, x1, y1;  ///< inclusive; empty if x0 > x1 or y0 > y1
};

}  // namespace

DepthCanvas::DepthCanvas(const ViewCamera& camera, const cv::Vec3b& background)
    : camera_(camera),
      // From above and a little left of the camera: tops bright, sides shaded.
      light_((-camera.forward + 1.2 * Eigen::Vector3d::UnitZ() - 0.4 * camera.right).normalized()),
      image_(camera.size, background),
      depth_(camera.size, std::numeric_limits<float>::infinity()) {}

void DepthCanvas::drawEllipsoid(const Eigen::Vector3d& centre, const Eigen::Matrix3d& shape,
                                const cv::Vec3b& bgr) {
  bool invertible = false;
  Eigen::Matrix3d m;
  shape.computeInverseWithCheck(m, invertible);
  if (!invertible || !m.allFinite()) return;
  // The screen box of the ellipsoid's axis-aligned bounding box.
  const Eigen::Vector3d half = shape.diagonal().cwiseMax(0.0).cwiseSqrt();
  PixelBox box{camera_.size.width, camera_.size.height, -1, -1};
  for (int corner = 0; corner < 8; ++corner) {
    const Eigen::Vector3d p(centre.x() + (corner & 1 ? half.x() : -half.x()),
                            centre.y() + (corner & 2 ? half.y() : -half.y()),
                            centre.z() + (corner & 4 ? half.z() : -half.z()));
    const Eigen::Vector3d s = camera_.project(p);
    if (!(s.z() > 0)) return;  // reaches behind the eye: its screen box is unbounded
    box.x0 = std::min(box.x0, int(std::floor(s.x())));
    box.y0 = std::min(box.y0, int(std::floor(s.y())));
    box.x1 = std::max(box.x1, int(std::ceil(s.x())));
    box.y1 = std::max(box.y1, int(std::ceil(s.y())));
  }
  box = {std::max(box.x0, 0), std::max(box.y0, 0), std::min(box.x1, camera_.size.width - 1),
         std::min(box.y1, camera_.size.height - 1)};

  // Along the ray eye + t·d, d = f + X·r + Y·u, the surface is a·t² + 2h·t + c = 0 with
  // a = dᵀMd and h = dᵀM(eye − centre), quadratic and linear in the pixel's (X, Y).
  const Eigen::Vector3d &f = camera_.forward, &r = camera_.right, &u = camera_.up;
  const Eigen::Vector3d mf = m * f, mr = m * r, mu = m * u, me = m * (camera_.eye - centre);
  const double c = (camera_.eye - centre).dot(me) - 1;
  if (!(c > 0)) return;  // the eye is inside
  const double ff = f.dot(mf), rr = r.dot(mr), uu = u.dot(mu), fr = f.dot(mr), fu = f.dot(mu),
               ru = r.dot(mu), ef = me.dot(f), er = me.dot(r), eu = me.dot(u);
  const double inv_focal = 1.0 / camera_.focal_px;
  for (int y = box.y0; y <= box.y1; ++y) {
    const double ys = (0.5 * camera_.size.height - (y + 0.5)) * inv_focal;
    const double a0 = ff + 2 * ys * fu + ys * ys * uu, a1 = 2 * (fr + ys * ru), h0 = ef + ys * eu;
    float* depth_row = depth_.ptr<float>(y);
    cv::Vec3b* image_row = image_.ptr<cv::Vec3b>(y);
    for (int x = box.x0; x <= box.x1; ++x) {
      const double xs = (x + 0.5 - 0.5 * camera_.size.width) * inv_focal;
      const double a = a0 + xs * (a1 + xs * rr), h = h0 + xs * er;
      const double disc = h * h - a * c;
      if (disc < 0) continue;
      const double t = (-h - std::sqrt(disc)) / a;  // the nearer crossing
      if (!(t > 0) || t >= depth_row[x]) continue;
      depth_row[x] = float(t);
      const Eigen::Vector3d normal = (me + t * (mf + xs * mr + ys * mu)).normalized();
      const double shade = kAmbient + kDiffuse * std::max(0.0, normal.dot(light_));
      for (int k = 0; k < 3; ++k)
        image_row[x][k] = uint8_t(std::min(255.0, std::round(shade * bgr[k])));
    }
  }
}

void DepthCanvas::drawPolyline(const std::vector<Eigen::Vector3d>& points, const cv::Vec3b& bgr,
                               int width_px) {
  const int radius = std::max(0, width_px / 2);
  for (size_t i = 1; i < points.size(); ++i) {
    const Eigen::Vector3d a = camera_.project(points[i - 1]), b = camera_.project(points[i]);
    if (!(a.z() > 0 && b.z() > 0)) continue;
    const double length_px = std::hypot(b.x() - a.x(), b.y() - a.y());
    if (!std::isfinite(length_px)) continue;
    const int steps = int(std::ceil(2 * length_px)) + 1;
    for (int s = 0; s <= steps; ++s) {
      // Sampled in space, then projected: the depth of each sample is exact.
      const Eigen::Vector3d p =
          camera_.project(points[i - 1] + (points[i] - points[i - 1]) * (double(s) / steps));
      const int cx = int(std::floor(p.x())), cy = int(std::floor(p.y()));
      for (int y = cy - radius; y <= cy + radius; ++y)
        for (int x = cx - radius; x <= cx + radius; ++x) {
          if (x < 0 || y < 0 || x >= camera_.size.width || y >= camera_.size.height) continue;
          if (p.z() > depth_(y, x)) continue;
          image_(y, x) = bgr;
        }
    }
  }
}

}  // namespace ndtom::apps
