// A .ndtom file of format version 1 (one record per cell, still read: map_io.h) written field
// by field, with a correct checksum: an oracle independent of the encoder, for tests and the
// red team's hostile files. Version 1 keeps every cell value in a fixed place, so a hostile
// value is easy to plant; the loader applies the same cell rule to both versions.
#pragma once

#include <cstdint>
#include <cstring>
#include <string>
#include <utility>
#include <vector>

#include "ndtom/map/cell_index.h"
#include "ndtom/map/cell_stats.h"
#include "ndtom/map/options.h"
#include "ndtom_internal/crc32.h"

namespace ndtom::testing {

class FileBuilder {
 public:
  /// The options of `o`, except `replaced` (if given) stored as `value`.
  explicit FileBuilder(const MapOptions& o = {}, const std::string& replaced = "",
                       double value = 0) {
    bytes("NDTOMMAP", 8);
    u32(1);
    const std::pair<const char*, double> options[] = {
        {"resolution", o.resolution},
        {"occupancy_enabled", o.occupancy.enabled ? 1.0 : 0.0},
        {"p_hit", o.occupancy.p_hit},
        {"p_miss", o.occupancy.p_miss},
        {"logodds_min", o.occupancy.logodds_min},
        {"logodds_max", o.occupancy.logodds_max},
        {"min_range", o.scan.min_range},
        {"max_range", o.scan.max_range},
        {"ray_mode", double(int(o.scan.ray_mode))},
        {"min_eigen_ratio", o.regularization.min_eigen_ratio},
        {"min_eigen_abs", o.regularization.min_eigen_abs}};
    u32(11);
    for (const auto& [name, stored] : options) {
      out_.push_back(uint8_t(std::strlen(name)));
      bytes(name, std::strlen(name));
      f64(name == replaced ? value : stored);
    }
  }
  void cells(uint64_t n) { u64(n); }
  void cell(const CellIndex& c, float logodds, const CellStats& s = {}) {
    for (int a = 0; a < 3; ++a) u32(uint32_t(c[a]));
    uint32_t l;
    std::memcpy(&l, &logodds, 4);
    u32(l);
    u32(s.n);
    if (s.n == 0) return;
    for (int a = 0; a < 3; ++a) f64(s.relative_mean[a]);
    const auto& m = s.scatter;
    for (const double v : {m(0, 0), m(0, 1), m(0, 2), m(1, 1), m(1, 2), m(2, 2)}) f64(v);
  }
  /// Raw bytes, e.g. a field of a damaged file.
  void bytes(const void* p, size_t n) {
    out_.insert(out_.end(), static_cast<const uint8_t*>(p), static_cast<const uint8_t*>(p) + n);
  }
  /// The bytes so far and their CRC.
  std::vector<uint8_t> finish() const {
    std::vector<uint8_t> b = out_;
    const uint32_t crc = crc32(b.data(), b.size());
    for (int i = 0; i < 4; ++i) b.push_back(uint8_t(crc >> (8 * i)));
    return b;
  }

 private:
  void u32(uint32_t v) { bytes(&v, 4); }  // little-endian hosts, as the project
  void u64(uint64_t v) { bytes(&v, 8); }
  void f64(double v) { bytes(&v, 8); }

  std::vector<uint8_t> out_;
};

}  // namespace ndtom::testing
