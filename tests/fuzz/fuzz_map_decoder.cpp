// Fuzz target: the .ndtom decoder behind the checksum. The input's last 4 bytes are replaced
// by the CRC of the rest, so mutations reach the structural checks (with a random CRC almost
// every input stops at the checksum). Where the decoder accepts, the map must hold exactly
// the input: its options and cells, read here independently from the layout in map_io.h,
// and it must encode to bytes that decode to the same map.
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <map>
#include <string>
#include <vector>

#include "ndtom/crc32.h"
#include "ndtom/map_io.h"

namespace {

void check(bool ok) {
  if (!ok) std::abort();
}

// The documented layout, read without any check beyond bounds (the decoder accepted it).
struct Reader {
  const uint8_t* p;
  size_t left;
  template <class T>
  T get() {
    check(left >= sizeof(T));
    T v;
    std::memcpy(&v, p, sizeof(T));  // little-endian hosts, as the project
    p += sizeof(T), left -= sizeof(T);
    return v;
  }
};

struct Parsed {
  std::map<std::string, uint64_t> options;  // name -> bits of the f64
  struct Cell {
    float logodds;
    uint32_t n;
    double values[9];
  };
  std::map<ndtom::CellIndex, Cell> cells;
};

Parsed parse(const uint8_t* data, size_t size) {
  Reader in{data + 12, size - 12};  // magic, version
  Parsed out;
  for (uint32_t k = in.get<uint32_t>(); k > 0; --k) {
    std::string name(in.get<uint8_t>(), '\0');
    for (char& c : name) c = char(in.get<uint8_t>());
    out.options[name] = in.get<uint64_t>();
  }
  for (uint64_t k = in.get<uint64_t>(); k > 0; --k) {
    ndtom::CellIndex c{in.get<int32_t>(), in.get<int32_t>(), in.get<int32_t>()};
    Parsed::Cell cell{in.get<float>(), in.get<uint32_t>(), {}};
    if (cell.n > 0)
      for (double& v : cell.values) v = in.get<double>();
    check(out.cells.emplace(c, cell).second);
  }
  check(in.left == 4);
  return out;
}

bool sameBits(double a, double b) {
  return std::memcmp(&a, &b, sizeof(a)) == 0;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 16) return 0;
  std::vector<uint8_t> file(data, data + size);
  const uint32_t crc = ndtom::crc32(file.data(), file.size() - 4);
  for (int i = 0; i < 4; ++i) file[file.size() - 4 + size_t(i)] = uint8_t(crc >> (8 * i));
  ndtom::NdtMap map;
  try {
    map = ndtom::decodeMap(file.data(), file.size(), "fuzz", 64000000);
  } catch (const ndtom::MapFormatError&) {
    return 0;
  } catch (const ndtom::MemoryBudgetError&) {
    return 0;
  }
  // Decoded == input: the same options and cells, bit for bit.
  const Parsed input = parse(file.data(), file.size());
  const auto bytes = ndtom::encodeMap(map);
  const Parsed output = parse(bytes.data(), bytes.size());
  check(input.options == output.options);
  check(map.numCells() == input.cells.size() && output.cells.size() == input.cells.size());
  for (const auto& [index, cell] : input.cells) {
    const auto view = map.cell(index);
    check(view.has_value());
    check(std::memcmp(&view->logodds, &cell.logodds, 4) == 0);
    check((view->stats ? view->stats->n : 0) == cell.n);
    if (cell.n == 0) continue;
    const auto& s = *view->stats;
    const double values[9] = {s.mean[0],       s.mean[1],       s.mean[2],
                              s.scatter(0, 0), s.scatter(0, 1), s.scatter(0, 2),
                              s.scatter(1, 1), s.scatter(1, 2), s.scatter(2, 2)};
    for (int k = 0; k < 9; ++k) check(sameBits(values[k], cell.values[k]));
  }
  // And the map's own bytes load back to the same bytes.
  check(ndtom::encodeMap(ndtom::decodeMap(bytes.data(), bytes.size(), "re-encoded")) == bytes);
  return 0;
}
