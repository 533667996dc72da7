// Fuzz target: the PCD reader. Any input either parses or throws PcdError.
#include <cstddef>
#include <cstdint>
#include <string>

#include "ndtom_io/pcd_reader.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  try {
    const auto cloud =
        ndtom::io::parsePcd(std::string(reinterpret_cast<const char*>(data), size), "fuzz.pcd");
    (void)cloud;
  } catch (const ndtom::io::PcdError&) {
  }
  return 0;
}
