// Fuzz target: the .ndtom loader. Any input either loads into a valid map, which then
// round-trips exactly, or is rejected with MapFormatError. Crashes, leaks, sanitizer reports
// and other exceptions are failures.
#include <cstddef>
#include <cstdint>
#include <cstdlib>

#include "ndtom/files/map_io.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  try {
    const ndtom::NdtMap map = ndtom::decodeMap(data, size, "fuzz");
    const auto bytes = ndtom::encodeMap(map);
    const ndtom::NdtMap again = ndtom::decodeMap(bytes.data(), bytes.size(), "re-encoded");
    if (ndtom::encodeMap(again) != bytes) std::abort();
  } catch (const ndtom::MapFormatError&) {
  }
  return 0;
}
