#include "ndtom/map_io.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <functional>
#include <unordered_set>

#include "ndtom/atomic_file.h"
#include "ndtom/cell_rules.h"
#include "ndtom/checked_size.h"
#include "ndtom/crc32.h"
#include "ndtom/input_file.h"

namespace ndtom {
namespace {

constexpr char kMagic[8] = {'N', 'D', 'T', 'O', 'M', 'M', 'A', 'P'};
constexpr size_t kCellHeaderBytes = 5 * 4;
constexpr size_t kCellStatsBytes = 9 * 8;
constexpr uint32_t kMaxOptions = 256;

// Encodes into a buffer handed to `sink` every kChunk bytes, with the running CRC: a map of
// any size is written through 1 MB of memory.
class ByteWriter {
 public:
  static constexpr size_t kChunk = size_t(1) << 20;
  explicit ByteWriter(const MapByteSink& sink) : sink_(sink) { out_.reserve(kChunk + 128); }
  void bytes(const void* p, size_t n) {
    const auto* b = static_cast<const uint8_t*>(p);
    out_.insert(out_.end(), b, b + n);
  }
  /// Hands over what is buffered if it is a chunk or more.
  void maybeFlush() {
    if (out_.size() >= kChunk) flush();
  }
  void flush() {
    crc_ = crc32(out_.data(), out_.size(), crc_);
    sink_(out_.data(), out_.size());
    out_.clear();
  }
  /// Appends the CRC of everything written and hands the rest over.
  void finish() {
    const uint32_t crc = crc32(out_.data(), out_.size(), crc_);
    u32(crc);
    sink_(out_.data(), out_.size());
    out_.clear();
  }
  void u8(uint8_t v) { out_.push_back(v); }
  void u32(uint32_t v) {
    for (int i = 0; i < 4; ++i) out_.push_back(uint8_t(v >> (8 * i)));
  }
  void u64(uint64_t v) {
    for (int i = 0; i < 8; ++i) out_.push_back(uint8_t(v >> (8 * i)));
  }
  void i32(int32_t v) { u32(uint32_t(v)); }
  void f32(float v) {
    uint32_t u;
    std::memcpy(&u, &v, 4);
    u32(u);
  }
  void f64(double v) {
    uint64_t u;
    std::memcpy(&u, &v, 8);
    u64(u);
  }

 private:
  const MapByteSink& sink_;
  std::vector<uint8_t> out_;
  uint32_t crc_ = 0;
};

class ByteReader {
 public:
  ByteReader(const uint8_t* data, size_t size, const std::string& source)
      : data_(data), size_(size), source_(source) {}

  size_t remaining() const { return size_ - pos_; }
  size_t position() const { return pos_; }
  [[noreturn]] void fail(const std::string& why) const {
    throw MapFormatError(source_ + ": " + why + " (at byte " + std::to_string(pos_) + ")");
  }
  void need(size_t n) const {
    if (remaining() < n) fail("truncated");
  }
  void bytes(void* p, size_t n) {
    need(n);
    std::memcpy(p, data_ + pos_, n);
    pos_ += n;
  }
  uint8_t u8() {
    need(1);
    return data_[pos_++];
  }
  uint32_t u32() {
    need(4);
    uint32_t v = 0;
    for (int i = 0; i < 4; ++i) v |= uint32_t(data_[pos_ + i]) << (8 * i);
    pos_ += 4;
    return v;
  }
  uint64_t u64() {
    need(8);
    uint64_t v = 0;
    for (int i = 0; i < 8; ++i) v |= uint64_t(data_[pos_ + i]) << (8 * i);
    pos_ += 8;
    return v;
  }
  int32_t i32() { return int32_t(u32()); }
  float f32() {
    const uint32_t u = u32();
    float v;
    std::memcpy(&v, &u, 4);
    return v;
  }
  double f64() {
    const uint64_t u = u64();
    double v;
    std::memcpy(&v, &u, 8);
    return v;
  }

 private:
  const uint8_t* data_;
  size_t size_;
  size_t pos_ = 0;
  std::string source_;
};

/// Every option the file stores, with how to read it from and write it into MapOptions.
struct OptionField {
  const char* name;
  std::function<double(const MapOptions&)> get;
  std::function<void(MapOptions&, double)> set;
};

const std::vector<OptionField>& optionFields() {
  static const std::vector<OptionField> fields = {
      {"resolution", [](const MapOptions& o) { return o.resolution; },
       [](MapOptions& o, double v) { o.resolution = v; }},
      {"occupancy_enabled", [](const MapOptions& o) { return o.occupancy.enabled ? 1.0 : 0.0; },
       [](MapOptions& o, double v) {
         // Exactly 0 or 1: 0.5, 2 or NaN would otherwise read as true.
         if (v != 0.0 && v != 1.0) throw std::invalid_argument("occupancy_enabled: not 0 or 1");
         o.occupancy.enabled = v == 1.0;
       }},
      {"p_hit", [](const MapOptions& o) { return o.occupancy.p_hit; },
       [](MapOptions& o, double v) { o.occupancy.p_hit = v; }},
      {"p_miss", [](const MapOptions& o) { return o.occupancy.p_miss; },
       [](MapOptions& o, double v) { o.occupancy.p_miss = v; }},
      {"logodds_min", [](const MapOptions& o) { return o.occupancy.logodds_min; },
       [](MapOptions& o, double v) { o.occupancy.logodds_min = v; }},
      {"logodds_max", [](const MapOptions& o) { return o.occupancy.logodds_max; },
       [](MapOptions& o, double v) { o.occupancy.logodds_max = v; }},
      {"min_range", [](const MapOptions& o) { return o.insertion.min_range; },
       [](MapOptions& o, double v) { o.insertion.min_range = v; }},
      {"max_range", [](const MapOptions& o) { return o.insertion.max_range; },
       [](MapOptions& o, double v) { o.insertion.max_range = v; }},
      {"ray_mode", [](const MapOptions& o) { return double(int(o.insertion.ray_mode)); },
       [](MapOptions& o, double v) {
         if (v != 0.0 && v != 1.0) throw std::invalid_argument("ray_mode: unknown value");
         o.insertion.ray_mode = RayMode(int(v));
       }},
      {"min_eigen_ratio", [](const MapOptions& o) { return o.regularization.min_eigen_ratio; },
       [](MapOptions& o, double v) { o.regularization.min_eigen_ratio = v; }},
      {"min_eigen_abs", [](const MapOptions& o) { return o.regularization.min_eigen_abs; },
       [](MapOptions& o, double v) { o.regularization.min_eigen_abs = v; }},
  };
  return fields;
}

MapOptions readOptions(ByteReader& in) {
  const uint32_t count = in.u32();
  if (count > kMaxOptions) in.fail("implausible option count " + std::to_string(count));
  MapOptions options;
  std::unordered_set<std::string> seen;
  for (uint32_t k = 0; k < count; ++k) {
    std::string name(in.u8(), '\0');
    in.bytes(name.data(), name.size());
    const double value = in.f64();  // max_range may be +inf; validate() judges the values
    const auto& fields = optionFields();
    const auto it = std::find_if(fields.begin(), fields.end(),
                                 [&](const OptionField& f) { return name == f.name; });
    if (it == fields.end()) in.fail("unknown option '" + name + "'");
    if (!seen.insert(name).second) in.fail("option '" + name + "' given twice");
    try {
      it->set(options, value);
    } catch (const std::invalid_argument& e) {
      in.fail(e.what());
    }
  }
  if (seen.size() != optionFields().size()) in.fail("missing options");
  try {
    validate(options);
  } catch (const std::invalid_argument& e) {
    in.fail(std::string("bad option: ") + e.what());
  }
  return options;
}

}  // namespace

uint64_t encodedMapSize(const NdtMap& map) {
  uint64_t size = sizeof(kMagic) + 4 + 4 + 8 + 4;  // magic, version, option count, cells, CRC
  for (const OptionField& f : optionFields()) size += 1 + std::strlen(f.name) + 8;
  size += uint64_t(map.numCells()) * kCellHeaderBytes;
  map.forEachCell([&](const CellView& c) { size += c.stats ? kCellStatsBytes : 0; });
  return size;
}

void encodeMap(const NdtMap& map, const MapByteSink& sink) {
  ByteWriter w(sink);
  w.bytes(kMagic, sizeof(kMagic));
  w.u32(kMapFormatVersion);
  w.u32(uint32_t(optionFields().size()));
  for (const OptionField& f : optionFields()) {
    const std::string name = f.name;
    w.u8(uint8_t(name.size()));
    w.bytes(name.data(), name.size());
    w.f64(f.get(map.options()));
  }
  w.u64(map.numCells());
  map.forEachCellOrdered([&](const CellView& c) {
    w.i32(c.index.x);
    w.i32(c.index.y);
    w.i32(c.index.z);
    w.f32(c.logodds);
    const uint32_t n = c.stats ? c.stats->n : 0;
    w.u32(n);
    if (n > 0) {
      for (int a = 0; a < 3; ++a) w.f64(c.stats->mean[a]);
      const Eigen::Matrix3d& s = c.stats->scatter;
      for (const double v : {s(0, 0), s(0, 1), s(0, 2), s(1, 1), s(1, 2), s(2, 2)}) w.f64(v);
    }
    w.maybeFlush();
  });
  w.finish();
}

std::vector<uint8_t> encodeMap(const NdtMap& map) {
  std::vector<uint8_t> out;
  out.reserve(size_t(encodedMapSize(map)));
  encodeMap(map,
            [&](const uint8_t* data, size_t size) { out.insert(out.end(), data, data + size); });
  return out;
}

NdtMap decodeMap(const uint8_t* data, size_t size, const std::string& source,
                 uint64_t memory_budget) {
  ByteReader in(data, size, source);
  char magic[sizeof(kMagic)];
  in.bytes(magic, sizeof(magic));
  if (std::memcmp(magic, kMagic, sizeof(kMagic)) != 0) in.fail("not an NDT-OM map file");
  if (size < sizeof(kMagic) + 8) in.fail("truncated");
  const uint32_t stored_crc = ByteReader(data + size - 4, 4, source).u32();
  if (crc32(data, size - 4) != stored_crc) in.fail("checksum mismatch: the data is damaged");

  const uint32_t version = in.u32();
  if (version != kMapFormatVersion)
    in.fail("unsupported format version " + std::to_string(version));
  MapOptions options = readOptions(in);
  options.insertion.memory_budget = memory_budget;
  NdtMap map(options);

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
      for (int a = 0; a < 3; ++a) stats.mean[a] = in.f64();
      Eigen::Matrix3d& s = stats.scatter;
      s(0, 0) = in.f64();
      s(0, 1) = s(1, 0) = in.f64();
      s(0, 2) = s(2, 0) = in.f64();
      s(1, 1) = in.f64();
      s(1, 2) = s(2, 1) = in.f64();
      s(2, 2) = in.f64();
    }
    if (const char* problem = cellProblem(index, logodds, stats, map.options())) in.fail(problem);
    try {
      if (!map.setCell(index, logodds, stats)) in.fail("duplicate cell");
    } catch (const MemoryBudgetError& e) {
      throw MemoryBudgetError(source + ": loading " + std::to_string(cells) + " cells", e.needed(),
                              e.budget());
    }
  }
  if (in.remaining() != 4) in.fail("unexpected bytes after the cells");
  map.shrinkToFit();
  return map;
}

void saveMap(const NdtMap& map, const std::string& path) {
  writeFileAtomically(path, [&](const FileSink& write) {
    encodeMap(map, [&](const uint8_t* data, size_t size) { write(data, size); });
  });
}

NdtMap loadMap(const std::string& path, uint64_t memory_budget) {
  // The whole file is read: one larger than the budget cannot load within it.
  const uint64_t size = checkInputFile(path, UINT64_MAX, "map file");
  if (size > memory_budget)
    throw MemoryBudgetError("loading map file " + path, size, memory_budget);
  const std::string bytes = readInputFile(path, memory_budget, "map file");
  return decodeMap(reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size(), path,
                   memory_budget);
}

}  // namespace ndtom
