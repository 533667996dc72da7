// registerClasses(): the explicit counterpart of the static registration in CNDTOccupancyMap.cpp.
#include "mrpt_ndtom/register_classes.h"

#include <mrpt/maps/TMetricMapTypesRegistry.h>
#include <mrpt/rtti/CObject.h>

#include <stdexcept>

#include "mrpt_ndtom/CNDTOccupancyMap.h"

namespace mrpt_ndtom {

void registerClasses() {
  // Both registrations ran when the library was loaded; registering the class again only
  // overwrites the same entry, so this is safe to call any number of times.
  mrpt::rtti::registerClass(CLASS_ID(CNDTOccupancyMap));
  const auto& maps = mrpt::maps::internal::TMetricMapTypesRegistry::Instance().getAllRegistered();
  if (maps.count("ndtOccupancyMap") == 0 || maps.count("mrpt_ndtom::CNDTOccupancyMap") == 0)
    throw std::logic_error("mrpt_ndtom::registerClasses: CNDTOccupancyMap is not registered");
}

}  // namespace mrpt_ndtom
