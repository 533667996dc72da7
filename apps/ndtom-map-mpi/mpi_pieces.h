// MPI counts are ints: a buffer of a 64-bit size is sent in pieces.
#pragma once

#include <algorithm>
#include <climits>
#include <cstdint>

namespace ndtom::mapper {

/// Calls f(offset, size) for consecutive pieces of at most INT_MAX / 2 bytes covering `bytes`.
template <class F>
void forEachMpiPiece(uint64_t bytes, F&& f) {
  constexpr uint64_t kPiece = INT_MAX / 2;
  for (uint64_t done = 0; done < bytes; done += kPiece) f(done, int(std::min(kPiece, bytes - done)));
}

}  // namespace ndtom::mapper
