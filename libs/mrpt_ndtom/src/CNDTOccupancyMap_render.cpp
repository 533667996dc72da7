// CNDTOccupancyMap: drawing and saving a viewable representation.
#include <mrpt/opengl/COpenGLScene.h>

#include "mrpt_ndtom/CNDTOccupancyMap.h"
#include "ndtom/map_io.h"

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

}  // namespace mrpt_ndtom
