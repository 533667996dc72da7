// Fuzz target: scan insertion with arbitrary points (NaN/Inf, huge and tiny coordinates,
// zero-length rays, origins inside occupied cells). The bytes give the options, an origin and
// the points of up to three scans. Checked after every scan: the report accounts for every
// point, the map's invariant holds (statistics iff log-odds > 0, within the clamp), and a
// rejected scan (bad origin or options) leaves the map unchanged.
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <stdexcept>
#include <vector>

#include "ndtom/files/map_io.h"
#include "ndtom/map/ndt_map.h"

namespace {

class Bytes {
 public:
  Bytes(const uint8_t* data, size_t size) : data_(data), size_(size) {}
  bool empty() const { return pos_ >= size_; }
  uint8_t byte() { return pos_ < size_ ? data_[pos_++] : 0; }
  // Doubles are drawn both raw (any bit pattern: NaN, Inf, 1e300) and as small grid-aligned
  // values (rays through cell edges and corners, points in the origin's cell).
  double number() {
    if (byte() & 1) {
      uint64_t bits = 0;
      for (int i = 0; i < 8; ++i) bits |= uint64_t(byte()) << (8 * i);
      double v;
      std::memcpy(&v, &bits, 8);
      return v;
    }
    return (int(byte()) - 128) * 0.125;
  }

 private:
  const uint8_t* data_;
  size_t size_;
  size_t pos_ = 0;
};

void check(bool ok) {
  if (!ok) std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  Bytes in(data, size);
  ndtom::MapOptions options;
  const double resolutions[] = {0.05, 0.125, 0.25, 1.0};
  options.resolution = resolutions[in.byte() % 4];
  options.occupancy.enabled = in.byte() % 4 != 0;
  options.scan.ray_mode = in.byte() % 2 ? ndtom::RayMode::PerHitCell : ndtom::RayMode::PerPoint;
  options.scan.threads = in.byte() % 4 == 0 ? 2 : 1;
  options.scan.max_range = in.byte() % 2 ? 4.0 : INFINITY;
  ndtom::NdtMap map(options);

  for (int scan = 0; scan < 3 && !in.empty(); ++scan) {
    const Eigen::Vector3d origin(in.number(), in.number(), in.number());
    std::vector<Eigen::Vector3d> points(in.byte() % 64);
    for (auto& p : points) p = Eigen::Vector3d(in.number(), in.number(), in.number());
    const auto before = ndtom::encodeMap(map);
    try {
      const ndtom::InsertionReport r = map.insertScan(points, origin);
      check(r.pointsUsed() + r.rejected() == points.size());
      check(r.cells_hit <= r.cells_touched);
    } catch (const std::invalid_argument&) {
      check(ndtom::encodeMap(map) == before);
    }
    map.forEachCell([&](const ndtom::CellView& c) {
      check(std::isfinite(c.logodds));
      check(c.logodds >= float(options.occupancy.logodds_min));
      check(c.logodds <= float(options.occupancy.logodds_max));
      if (options.occupancy.enabled) check((c.stats != nullptr) == (c.logodds > 0));
      if (c.stats)
        check(c.stats->n > 0 && c.stats->relative_mean.allFinite() && c.stats->scatter.allFinite());
    });
  }
  const auto bytes = ndtom::encodeMap(map);
  check(ndtom::encodeMap(ndtom::decodeMap(bytes.data(), bytes.size())) == bytes);
  return 0;
}
