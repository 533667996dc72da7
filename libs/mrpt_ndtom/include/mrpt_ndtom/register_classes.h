#pragma once
// Registration of the plugin's classes with MRPT, for programs that link libmrpt_ndtom.so.

namespace mrpt_ndtom {

/// Makes sure CNDTOccupancyMap is registered with MRPT: as `ndtOccupancyMap` /
/// `mrpt_ndtom::CNDTOccupancyMap` for `.ini` files (TSetOfMetricMapInitializers,
/// CMultiMetricMap) and for deserialization. The library registers it when it is loaded; a
/// program that creates the map only from `.ini` text references no symbol of the library, so
/// a linker running with `--as-needed` (Debian's default) drops it and the map is silently
/// missing. Calling this function keeps the library linked. The CMake target
/// `ndtom::mrpt_ndtom` also links it with `--no-as-needed`, so the call is only required with
/// other build systems. Throws std::logic_error if the map type is not registered.
void registerClasses();

}  // namespace mrpt_ndtom
