// Memory of this process, from /proc/self/status (Linux).
#pragma once

#include <cstddef>

namespace ndtom::mapper {

size_t currentRssBytes();  ///< resident set size now; 0 if unknown
size_t peakRssBytes();     ///< largest resident set size so far; 0 if unknown

}  // namespace ndtom::mapper
