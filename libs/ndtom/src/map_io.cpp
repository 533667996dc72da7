#include "ndtom/map_io.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <functional>
#include <unordered_set>

#include "map_codec.h"
#include "ndtom/atomic_file.h"
#include "ndtom/cell_rules.h"
#include "ndtom/crc32.h"
#include "ndtom/input_file.h"

namespace ndtom {
namespace {

using detail::ByteReader;
using detail::ByteWriter;

constexpr char kMagic[8] = {'N', 'D', 'T', 'O', 'M', 'M', 'A', 'P'};
constexpr uint32_t kMaxOptions = 256;

/// By bits: −0 would load as false and save as +0, a file that does not load back to itself.
bool exactly0or1(double v) {
  return (v == 0.0 && !std::signbit(v)) || v == 1.0;
}

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
         if (!exactly0or1(v)) throw std::invalid_argument("occupancy_enabled: not 0 or 1");
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
         if (!exactly0or1(v)) throw std::invalid_argument("ray_mode: unknown value");
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

namespace detail {

void setDecodedCell(ByteReader& in, NdtMap& map, const CellIndex& index, float logodds,
                    const CellStats& stats, uint64_t cells) {
  if (const char* problem = cellProblem(index, logodds, stats, map.options())) in.fail(problem);
  try {
    if (!map.setCell(index, logodds, stats)) in.fail("duplicate cell");
  } catch (const MemoryBudgetError& e) {
    throw MemoryBudgetError(in.source() + ": loading " + std::to_string(cells) + " cells",
                            e.needed(), e.budget());
  }
}

}  // namespace detail

uint64_t encodedMapSize(const NdtMap& map) {
  // Counted, not computed: the runs and masks depend on the whole map.
  uint64_t size = 0;
  encodeMap(map, [&](const uint8_t*, size_t n) { size += n; });
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
  detail::encodeBlocks(map, w);
  w.finish();
}

std::vector<uint8_t> encodeMap(const NdtMap& map) {
  std::vector<uint8_t> out;  // not reserved: the size would take a second encoding
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
  if (version < kOldestMapFormatVersion || version > kMapFormatVersion)
    in.fail("unsupported format version " + std::to_string(version));
  MapOptions options = readOptions(in);
  options.insertion.memory_budget = memory_budget;
  NdtMap map(options);

  if (version == 1)
    detail::decodeCellRecords(in, map);
  else
    detail::decodeBlocks(in, map);
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
