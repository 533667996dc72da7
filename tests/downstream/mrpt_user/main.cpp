// Creates an NDT-OM from .ini text alone, inserts a point cloud of a wall and checks the map.
// Exit status: 0 the map is a CNDTOccupancyMap with cells; 3 no map was created (the plugin is
// not loaded); 1 any other failure.
#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/maps/CMultiMetricMap.h>
#include <mrpt/maps/CSimplePointsMap.h>
#include <mrpt/obs/CObservationPointCloud.h>
#include <mrpt/poses/CPose3D.h>

#include <cstdio>
#include <memory>
#include <string>

#ifdef CALL_REGISTER_CLASSES
#include <mrpt_ndtom/register_classes.h>
#endif

int main() {
#ifdef CALL_REGISTER_CLASSES
  mrpt_ndtom::registerClasses();
#endif
  const std::string ini = R"(
[MetricMap]
ndtOccupancyMap_count = 1
[MetricMap_ndtOccupancyMap_00_insertOpts]
resolution = 0.25
)";
  mrpt::config::CConfigFileMemory config(ini);
  mrpt::maps::TSetOfMetricMapInitializers initializers;
  initializers.loadFromConfigFile(config, "MetricMap");
  mrpt::maps::CMultiMetricMap maps;
  maps.setListOfMaps(initializers);
  const std::unique_ptr<mrpt::maps::TMetricMapInitializer> by_class(
      mrpt::maps::TMetricMapInitializer::factory("mrpt_ndtom::CNDTOccupancyMap"));
  if (maps.maps.empty() || !by_class) {
    std::printf("no map: %zu maps from the .ini, factory by class name %s\n", maps.maps.size(),
                by_class ? "ok" : "null");
    return 3;
  }

  // A 2 m x 1 m wall 3 m ahead of the sensor, points 5 cm apart, in the sensor frame.
  auto obs = mrpt::obs::CObservationPointCloud::Create();
  auto cloud = mrpt::maps::CSimplePointsMap::Create();
  for (int i = 0; i <= 40; ++i)
    for (int j = 0; j <= 20; ++j) cloud->insertPoint(3.0f, -1.0f + 0.05f * i, 0.05f * j);
  obs->pointcloud = cloud;
  const bool inserted = maps.insertObservation(*obs, mrpt::poses::CPose3D(1, 2, 0, 0, 0, 0));

  const auto& map = *maps.maps.at(0);
  const std::string class_name = map.GetRuntimeClass()->className;
  std::printf("%s, inserted %d, empty %d\n%s\n", class_name.c_str(), int(inserted),
              int(map.isEmpty()), map.asString().c_str());
  return maps.maps.size() == 1 && class_name == "mrpt_ndtom::CNDTOccupancyMap" && inserted &&
                 !map.isEmpty()
             ? 0
             : 1;
}
