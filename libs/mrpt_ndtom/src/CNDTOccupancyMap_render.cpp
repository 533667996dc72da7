// CNDTOccupancyMap: drawing and saving a viewable representation.
#include <mrpt/opengl/COpenGLScene.h>

#include <algorithm>
#include <cmath>

#include "mrpt_ndtom/CNDTOccupancyMap.h"
#include "ndtom/files/map_io.h"

namespace mrpt_ndtom {

void CNDTOccupancyMap::getVisualizationInto(mrpt::opengl::CSetOfObjects& outObj) const {
  if (!genericMapParams.enableSaveAs3DObject) return;
  buildNdtVisualization(m_map, renderOptions, outObj);
}

void CNDTOccupancyMap::saveMetricMapRepresentationToFile(const std::string& prefix) const {
  ndtom::saveMap(m_map, prefix + ".ndtom");
  mrpt::opengl::COpenGLScene scene;
  auto objects = mrpt::opengl::CSetOfObjects::Create();
  buildNdtVisualization(m_map, renderOptions, *objects);  // whatever enableSaveAs3DObject says
  scene.insert(objects);
  if (!scene.saveToFile(prefix + ".3Dscene"))
    THROW_EXCEPTION("CNDTOccupancyMap: cannot write " + prefix + ".3Dscene");
}

namespace {

uint8_t toByte(double v) {
  return uint8_t(std::clamp(std::lround(v), 0L, 255L));
}

// The colour of a voxel with occupancy `occ` at relative height `height` (both in [0, 1]),
// by the object's mode and colour: the scales COccupancyGridMap3D and COctoMap use.
mrpt::img::TColor voxelColor(const mrpt::opengl::COctoMapVoxels& gl, double occ, double height) {
  using V = mrpt::opengl::COctoMapVoxels;
  const mrpt::img::TColorf c = gl.getColor();
  const auto scaled = [&](double k, double alpha) {
    return mrpt::img::TColor(toByte(k * c.R), toByte(k * c.G), toByte(k * c.B), toByte(alpha));
  };
  const double by_freeness = 240 * (1 - occ) + 15, opacity = std::max(0.0, 255 - 510 * (1 - occ));
  switch (gl.getVisualizationMode()) {
    case V::COLOR_FROM_HEIGHT:
      return scaled(255 * height, 255 * c.A);
    case V::COLOR_FROM_OCCUPANCY:
      return scaled(by_freeness, 255 * c.A);
    case V::TRANSPARENCY_FROM_OCCUPANCY:
      return scaled(255, opacity);
    case V::TRANS_AND_COLOR_FROM_OCCUPANCY:
      return scaled(by_freeness, 50);
    case V::MIXED:
      return scaled(255 * height, opacity);
    case V::FIXED:
    default:
      return scaled(255, 255 * c.A);
  }
}

}  // namespace

void CNDTOccupancyMap::getAsOctoMapVoxels(mrpt::opengl::COctoMapVoxels& gl) const {
  using mrpt::opengl::VOXEL_SET_FREESPACE;
  using mrpt::opengl::VOXEL_SET_OCCUPIED;
  const TRenderOptions& o = renderOptions;
  gl.clear();
  gl.resizeVoxelSets(2);
  gl.showVoxels(VOXEL_SET_OCCUPIED, o.visible_occupied_voxels);
  gl.showVoxels(VOXEL_SET_FREESPACE, o.visible_free_voxels);
  const mrpt::math::TBoundingBox box = boundingBox();
  const double z_span = std::max(box.max.z - box.min.z, 1e-9);
  const double side = m_map.options().resolution;
  m_map.forEachCellOrdered([&](const ndtom::CellView& c) {
    const ndtom::CellState state = ndtom::cellState(m_map, c);
    const bool occupied = state == ndtom::CellState::Occupied;
    if (occupied ? !o.generate_occupied_voxels
                 : (state != ndtom::CellState::Free || !o.generate_free_voxels))
      return;
    const Eigen::Vector3d centre = m_map.geometry().cellCenter(c.index);
    const double occ = ndtom::occupancyProbability(c.logodds);
    const double height = (centre.z() - box.min.z) / z_span;
    gl.push_back_Voxel(
        occupied ? VOXEL_SET_OCCUPIED : VOXEL_SET_FREESPACE,
        {mrpt::math::TPoint3Df(float(centre.x()), float(centre.y()), float(centre.z())), side,
         voxelColor(gl, occ, height)});
  });
  if (gl.isCubeTransparencyEnabled()) gl.sort_voxels_by_z();
  gl.setBoundingBox(box.min, box.max);
}

}  // namespace mrpt_ndtom
