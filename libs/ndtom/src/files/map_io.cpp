#include "ndtom/files/map_io.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <unordered_set>

#include "files/map_codec.h"
#include "ndtom/map/cell_rules.h"
#include "ndtom/map/option_table.h"
#include "ndtom_internal/atomic_file.h"
#include "ndtom_internal/crc32.h"
#include "ndtom_internal/input_file.h"

namespace ndtom {
namespace {

using detail::ByteReader;
using detail::ByteWriter;

constexpr char kMagic[8] = {'N', 'D', 'T', 'O', 'M', 'M', 'A', 'P'};
constexpr uint32_t kMaxOptions = 256;

// The file stores the Map-scope rows of the option table, in its order, as (name, f64).
template <class F>
void forEachStoredOption(F&& f) {
  for (const OptionRow& row : kMapOptionRows)
    if (row.scope == OptionScope::Map) f(row);
}

size_t storedOptionCount() {
  size_t n = 0;
  forEachStoredOption([&](const OptionRow&) { ++n; });
  return n;
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
    const OptionRow* row = findOptionRow(name);
    if (!row || row->scope != OptionScope::Map) in.fail("unknown option '" + name + "'");
    if (!seen.insert(name).second) in.fail("option '" + name + "' given twice");
    // Before set(): a flag of 0.5, 2 or NaN would read as true, −0 would save back as +0.
    // Reals are judged with the other options by validate().
    if (row->type != OptionType::Real && !isOfOptionType(*row, value))
      in.fail(name + (row->type == OptionType::Bool ? ": not 0 or 1" : ": unknown value"));
    row->set(options, value);
  }
  if (seen.size() != storedOptionCount()) in.fail("missing options");
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
  w.u32(uint32_t(storedOptionCount()));
  forEachStoredOption([&](const OptionRow& row) {
    const std::string name = row.name;
    w.u8(uint8_t(name.size()));
    w.bytes(name.data(), name.size());
    w.f64(row.get(map.options()));
  });
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
  options.scan.memory_budget = memory_budget;
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
