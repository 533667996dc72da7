// CRC-32 (IEEE 802.3, as in zlib and PNG): detects damaged bytes in saved maps.
#pragma once

#include <cstddef>
#include <cstdint>

namespace ndtom {

/// Continues a CRC: pass the previous result as `crc` (0 to start).
uint32_t crc32(const void* data, size_t size, uint32_t crc = 0);

}  // namespace ndtom
