// Reading a CNDTOccupancyMap from an archive that may be corrupt. MRPT's operator>> for bool
// copies the stored byte into the bool as it is, and a byte other than 0 or 1 is not a valid
// bool: using it is undefined behaviour. So bools are read as bytes and checked, and bools
// that MRPT's own code has read (genericMapParams) are checked through their bytes before use.
#pragma once

#include <mrpt/core/exceptions.h>
#include <mrpt/core/format.h>
#include <mrpt/serialization/CArchive.h>

#include <cstdint>
#include <cstring>

namespace mrpt_ndtom::detail {

static_assert(sizeof(bool) == 1, "bools are stored as one byte");

/// A bool stored as one byte; throws naming `what` unless the byte is 0 or 1.
inline bool readBool(mrpt::serialization::CArchive& in, const char* what) {
  uint8_t byte = 0;
  in >> byte;
  if (byte > 1)
    THROW_EXCEPTION(mrpt::format("%s: stored bool is %u, not 0 or 1", what, unsigned(byte)));
  return byte == 1;
}

/// Throws naming `what` unless the bytes of `value` hold 0 or 1 (read without loading a bool).
inline void checkBoolBytes(const bool& value, const char* what) {
  uint8_t byte = 0;
  std::memcpy(&byte, &value, 1);
  if (byte > 1)
    THROW_EXCEPTION(mrpt::format("%s: stored bool is %u, not 0 or 1", what, unsigned(byte)));
}

}  // namespace mrpt_ndtom::detail
