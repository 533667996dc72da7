// Fuzz target: the tiled map reader (ndtom/files/tiled_map_io.h). The trailer's checksum is made
// right for the mutated header and index where their sizes allow, so mutations reach the index
// checks; each tile carries its own checksum. Any input either loads, and then saves and
// loads again to the same map, or is rejected with an exception derived from
// std::runtime_error (MapFormatError, MemoryBudgetError, unreadable file). Crashes, leaks,
// sanitizer reports and other exceptions are failures.
#include <unistd.h>

#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <string>

#include "ndtom/files/map_io.h"
#include "ndtom/files/tiled_map_io.h"
#include "ndtom_internal/crc32.h"

namespace {

uint64_t u64At(const std::string& b, size_t at) {
  uint64_t v = 0;
  std::memcpy(&v, b.data() + at, 8);  // little-endian hosts, as the project
  return v;
}

// The checksum over the header (24 bytes and the options block), the index and its offset.
void fixChecksum(std::string& b) {
  if (b.size() < 24 + 12) return;
  const uint64_t header = 24 + u64At(b, 16), index_at = u64At(b, b.size() - 12);
  if (header > b.size() || index_at > b.size() - 4 || header > index_at) return;
  const uint32_t crc =
      ndtom::crc32(b.data() + index_at, b.size() - 4 - index_at, ndtom::crc32(b.data(), header));
  std::memcpy(b.data() + b.size() - 4, &crc, 4);
}

std::string scratchPath(const char* what) {
  return "/tmp/ndtom_fuzz_tiles_" + std::to_string(::getpid()) + what;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::string bytes(reinterpret_cast<const char*>(data), size);
  fixChecksum(bytes);
  const std::string path = scratchPath(".in"), again = scratchPath(".again");
  std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;
  try {
    const ndtom::TiledMapFile file(path);
    const ndtom::NdtMap map = file.loadAll(64u << 20);
    ndtom::saveTiledMap(map, again, file.tileBlocks());
    const ndtom::NdtMap reloaded = ndtom::TiledMapFile(again).loadAll(64u << 20);
    if (ndtom::encodeMap(reloaded) != ndtom::encodeMap(map)) std::abort();
  } catch (const std::runtime_error&) {
  }
  std::remove(path.c_str());
  std::remove(again.c_str());
  return 0;
}
