// Version 1 of the cell section: a u64 count, then per cell i32 x y z, f32 log-odds, u32 N and,
// if N > 0, f64 mean[3] and f64 scatter[6] (xx xy xz yy yz zz). Kept so old files load.
#include "files/map_codec.h"
#include "ndtom_internal/checked_size.h"

namespace ndtom::detail {
namespace {

constexpr size_t kCellHeaderBytes = 5 * 4;

}  // namespace

void decodeCellRecords(ByteReader& in, NdtMap& map) {
  const uint64_t cells = in.u64();
  // Each cell takes at least kCellHeaderBytes, and the CRC follows them: a count is checked
  // against the bytes left before anything is allocated for it.
  if (in.remaining() < 4 || !fitsIn(cells, kCellHeaderBytes, in.remaining() - 4))
    in.fail("cell count " + std::to_string(cells) + " exceeds the file size");
  for (uint64_t k = 0; k < cells; ++k) {
    CellIndex index;
    for (int a = 0; a < 3; ++a) index[a] = in.i32();
    const float logodds = in.f32();
    CellStats stats;
    stats.n = in.u32();
    if (stats.n > 0) {
      for (int a = 0; a < 3; ++a) stats.relative_mean[a] = in.f64();
      stats.scatter = readScatter(in);
    }
    setDecodedCell(in, map, index, logodds, stats, cells);
  }
}

}  // namespace ndtom::detail
