// Fuzz target: the .ndtom decoder behind the checksum. The input's last 4 bytes are replaced
// by the CRC of the rest, so mutations reach the structural checks (with a random CRC almost
// every input stops at the checksum). Where the decoder accepts, the map must hold exactly
// the input: its options and cells, read here independently from the layouts in map_io.h
// (versions 1 and 2), and it must encode to bytes that decode to the same map.
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <map>
#include <string>
#include <vector>

#include "ndtom/files/map_io.h"
#include "ndtom_internal/crc32.h"

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

uint64_t varint(Reader& in) {
  uint64_t v = 0;
  for (int shift = 0;; shift += 7) {
    check(shift < 64);
    const uint8_t b = in.get<uint8_t>();
    v |= uint64_t(b & 0x7F) << shift;
    if (!(b & 0x80)) return v;
  }
}

// Version 2: blocks with presence masks, log-odds by dictionary and runs.
void parseBlocks(Reader& in, Parsed& out) {
  const uint64_t cells = in.get<uint64_t>();
  const uint64_t blocks = in.get<uint64_t>();
  const uint8_t coding = in.get<uint8_t>();
  std::vector<float> dictionary;
  if (coding == 0)
    for (uint64_t k = varint(in); k > 0; --k) dictionary.push_back(in.get<float>());
  float value = 0;
  uint64_t left = 0;
  int64_t block[3] = {0, 0, 0};
  for (uint64_t b = 0; b < blocks; ++b) {
    for (int64_t& v : block) {
      const uint64_t z = varint(in);
      v += int64_t(z >> 1) ^ -int64_t(z & 1);
    }
    const uint64_t nonzero = in.get<uint64_t>();
    std::vector<int> offsets;
    for (int j = 0; j < 64; ++j)
      if ((nonzero >> j) & 1) {
        const uint8_t byte = in.get<uint8_t>();
        for (int bit = 0; bit < 8; ++bit)
          if ((byte >> bit) & 1) offsets.push_back(8 * j + bit);
      }
    std::vector<Parsed::Cell> block_cells(offsets.size(), Parsed::Cell{0, 0, {}});
    for (auto& cell : block_cells) {
      if (coding == 1) {
        cell.logodds = in.get<float>();
        continue;
      }
      if (left == 0) {
        const uint64_t head = varint(in);
        check((head >> 1) < dictionary.size());
        value = dictionary[head >> 1];
        left = head & 1 ? varint(in) + 2 : 1;
      }
      --left;
      cell.logodds = value;
    }
    std::vector<uint8_t> has((offsets.size() + 7) / 8, 0);
    if (varint(in) > 0)
      for (uint8_t& byte : has) byte = in.get<uint8_t>();
    for (size_t j = 0; j < offsets.size(); ++j) {
      Parsed::Cell& cell = block_cells[j];
      if ((has[j / 8] >> (j % 8)) & 1) {
        const uint64_t head = varint(in);
        cell.n = uint32_t(head >> 1);
        for (int k = 0; k < 3; ++k) cell.values[k] = in.get<double>();
        if (head & 1)
          for (int k = 3; k < 9; ++k) cell.values[k] = in.get<double>();
      }
      const int o = offsets[j];
      const ndtom::CellIndex c{int32_t(block[0] * 8 + (o & 7)),
                               int32_t(block[1] * 8 + ((o >> 3) & 7)),
                               int32_t(block[2] * 8 + (o >> 6))};
      check(out.cells.emplace(c, cell).second);
    }
  }
  check(left == 0 && out.cells.size() == cells);
}

Parsed parse(const uint8_t* data, size_t size) {
  Reader in{data + 8, size - 8};  // magic
  const uint32_t version = in.get<uint32_t>();
  Parsed out;
  for (uint32_t k = in.get<uint32_t>(); k > 0; --k) {
    std::string name(in.get<uint8_t>(), '\0');
    for (char& c : name) c = char(in.get<uint8_t>());
    out.options[name] = in.get<uint64_t>();
  }
  if (version == 2) {
    parseBlocks(in, out);
    check(in.left == 4);
    return out;
  }
  check(version == 1);
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
    const double values[9] = {s.relative_mean[0], s.relative_mean[1], s.relative_mean[2],
                              s.scatter(0, 0),    s.scatter(0, 1),    s.scatter(0, 2),
                              s.scatter(1, 1),    s.scatter(1, 2),    s.scatter(2, 2)};
    for (int k = 0; k < 9; ++k) check(sameBits(values[k], cell.values[k]));
  }
  // And the map's own bytes load back to the same bytes.
  check(ndtom::encodeMap(ndtom::decodeMap(bytes.data(), bytes.size(), "re-encoded")) == bytes);
  return 0;
}
