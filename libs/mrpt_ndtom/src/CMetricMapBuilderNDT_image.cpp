// CMetricMapBuilderNDT::saveCurrentEstimationToImage: a top view drawn straight into an
// image (no OpenGL context needed), occupied Gaussians' means in black, the path in red.
#include <mrpt/core/exceptions.h>
#include <mrpt/img/CImage.h>

#include <algorithm>
#include <cmath>

#include "mrpt_ndtom/CMetricMapBuilderNDT.h"
#include "ndtom/map/map_queries.h"

namespace mrpt_ndtom {
namespace {

constexpr double kPixelsPerCell = 2;
constexpr double kMaxPixels = 4000;
constexpr double kMarginMetres = 1;

// Metres to pixels: x to the right, y up.
struct TopView {
  Eigen::AlignedBox2d box;
  double scale = 1;  // pixels per metre
  int width() const { return int(std::ceil(box.sizes().x() * scale)) + 1; }
  int height() const { return int(std::ceil(box.sizes().y() * scale)) + 1; }
  int col(double x) const { return int(std::lround((x - box.min().x()) * scale)); }
  int row(double y) const { return height() - 1 - int(std::lround((y - box.min().y()) * scale)); }
};

TopView fit(Eigen::AlignedBox2d box, double resolution) {
  box.extend(box.min() - Eigen::Vector2d::Constant(kMarginMetres));
  box.extend(box.max() + Eigen::Vector2d::Constant(kMarginMetres));
  const double extent = box.sizes().maxCoeff();
  return {box, std::min(kPixelsPerCell / resolution, kMaxPixels / extent)};
}

}  // namespace

void CMetricMapBuilderNDT::saveCurrentEstimationToImage(const std::string& file, bool) {
  std::lock_guard<std::mutex> lock(m_lock);
  const ndtom::NdtMap& map = m_mapper->ndtMap();
  std::vector<Eigen::Vector2d> cells;
  Eigen::AlignedBox2d box(Eigen::Vector2d(m_pose.mean.x(), m_pose.mean.y()));
  map.forEachCell([&](const ndtom::CellView& cell) {
    if (!ndtom::isOccupiedGaussian(map, cell)) return;
    const Eigen::Vector3d mean = map.gaussianOf(cell).mean;
    cells.push_back(mean.head<2>());
    box.extend(cells.back());
  });
  for (const TStep& step : m_steps) box.extend(Eigen::Vector2d(step.pose.x(), step.pose.y()));
  const TopView view = fit(box, map.options().resolution);
  mrpt::img::CImage image(unsigned(view.width()), unsigned(view.height()), mrpt::img::CH_RGB);
  image.filledRectangle(0, 0, view.width() - 1, view.height() - 1, mrpt::img::TColor::white());
  // Each Gaussian a square of its cell's size (at least a pixel).
  const int dot = std::max(1, int(std::lround(view.scale * map.options().resolution))) - 1;
  for (const Eigen::Vector2d& c : cells)
    image.filledRectangle(view.col(c.x()), view.row(c.y()), view.col(c.x()) + dot,
                          view.row(c.y()) + dot, mrpt::img::TColor::black());
  for (size_t i = 1; i < m_steps.size(); ++i) {
    const mrpt::poses::CPose3D& a = m_steps[i - 1].pose;
    const mrpt::poses::CPose3D& b = m_steps[i].pose;
    image.line(view.col(a.x()), view.row(a.y()), view.col(b.x()), view.row(b.y()),
               mrpt::img::TColor::red(), 2);
  }
  if (!image.saveToFile(file))
    THROW_EXCEPTION("CMetricMapBuilderNDT: cannot write the image " + file);
}

}  // namespace mrpt_ndtom
