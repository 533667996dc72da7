// Writers of hostile map files for issue #38's categories, with the library's own writers:
// maps that load but cost far more than their file size, or hold values that overflow
// downstream. They run as `ndtom-redteam --write ...` in a child process, so that the
// harness's own memory does not grow with the maps it writes.
#pragma once

#include <string>
#include <vector>

namespace redteam {

/// `ndtom-redteam --write KIND ARGS...`:
///   sparse FORMAT LAYOUT BLOCKS PATH [TILE_BLOCKS]
///                        a map of one Gaussian per block, BLOCKS blocks around the origin:
///                        LAYOUT cube (adjacent blocks) or grid (a square of the z = 0 layer,
///                        16 blocks apart); FORMAT ndtom | ndtommap (gzip'd MRPT archive) |
///                        tiles (.ndtomtiles, TILE_BLOCKS blocks a side)
///   scatter IN OUT VALUE the .ndtom IN with every Gaussian's scatter set to diag(VALUE),
///                        as .ndtom OUT
/// Returns the exit status (0 written, 1 failed with a message on stderr).
int writeHostileMap(const std::vector<std::string>& args);

}  // namespace redteam
