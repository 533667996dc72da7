// The second way a distributed build's processes can share a scan's free-space rays: each
// walks a share of the rays whole, through every tile, and sends the counts it made in other
// processes' tiles to their owners, which add them to theirs (with per-point rays each takes
// a share of the points and sends their hits to the owners too). Counts are integers, so every
// cell's sum, and so the map, is the serial one. The other way (owned_ray_walk.h) needs no
// messages, but every process repeats the per-ray work of every ray.
#pragma once

#include <cstdint>
#include <vector>

namespace ndtom {

/// Moves one scan's counts between the processes (MPI in ndtom-map-mpi, threads in tests).
class CountExchange {
 public:
  virtual ~CountExchange() = default;
  /// Every process calls it the same number of times per scan (once, or twice with per-point
  /// rays), in scan order. Sends outgoing[r] to process r
  /// (outgoing[own rank] is empty) and sets incoming[r] to what process r sent this one.
  /// `failed`: this process cannot insert the scan. Returns false if any process failed: then
  /// nothing is exchanged, and no process changes its map.
  virtual bool exchange(bool failed, const std::vector<std::vector<uint32_t>>& outgoing,
                        std::vector<std::vector<uint32_t>>& incoming) = 0;
};

}  // namespace ndtom
