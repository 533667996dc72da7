#include "scale/spill_codec.h"

#include <array>
#include <bitset>
#include <cstring>

#include "files/byte_io.h"
#include "map/map_internals.h"
#include "ndtom_internal/crc32.h"

namespace ndtom {
namespace {

constexpr char kSpillMagic[8] = {'N', 'D', 'T', 'O', 'M', 'S', 'P', 'L'};
constexpr size_t kStatsBytes = 4 + 12 * 8;

using Words = std::array<uint64_t, MapBlock::kWords>;  ///< a cell mask, 64 cells a word

Words wordsOf(const std::bitset<kBlockCells>& cells) {
  Words w{};
  for (size_t i = cells._Find_first(); i < kBlockCells; i = cells._Find_next(i))
    w[i >> 6] |= uint64_t(1) << (i & 63);
  return w;
}

int cellsIn(const Words& w) {
  int n = 0;
  for (const uint64_t word : w) n += __builtin_popcountll(word);
  return n;
}

/// f(offset) for every set bit, ascending.
template <class F>
void forEachBit(const Words& w, F&& f) {
  for (int k = 0; k < MapBlock::kWords; ++k)
    for (uint64_t word = w[size_t(k)]; word; word &= word - 1) f(64 * k + __builtin_ctzll(word));
}

}  // namespace

void SpillCodec::write(const NdtMap& map, const MapByteSink& sink) {
  detail::ByteWriter out(sink);  // in chunks, with the running CRC appended by finish()
  out.bytes(kSpillMagic, sizeof kSpillMagic);
  // Blocks without a known cell (insertion can leave some) are not part of the map: dropped.
  uint64_t blocks = 0;
  for (const auto& entry : MapInternals::grid(map).blocks()) blocks += entry.second->known.any();
  out.bytes(&blocks, 8);
  for (const auto& [index, block] : MapInternals::grid(map).blocks()) {
    if (block->known.none()) continue;
    out.bytes(&index, sizeof index);
    const Words known = wordsOf(block->known);
    out.bytes(known.data(), sizeof known);
    std::array<float, kBlockCells> values;
    int k = 0;
    const auto& logodds = block->logodds;  // a structured binding cannot be captured in C++17
    forEachBit(known, [&](int i) { values[size_t(k++)] = logodds[size_t(i)]; });
    out.bytes(values.data(), 4 * size_t(k));
    out.bytes(block->has_stats.data(), sizeof block->has_stats);
    const uint32_t count = uint32_t(block->stats.size());
    out.bytes(&count, 4);
    for (const CellStats& s : block->stats) {
      out.bytes(&s.n, 4);
      out.bytes(s.relative_mean.data(), 3 * 8);
      out.bytes(s.scatter.data(), 9 * 8);
    }
    out.maybeFlush();
  }
  out.finish();
}

NdtMap SpillCodec::read(const std::string& bytes, const MapOptions& options,
                        const std::string& source) {
  const auto* data = reinterpret_cast<const uint8_t*>(bytes.data());
  const std::string name = "spill file " + source;
  if (bytes.size() < sizeof kSpillMagic + 8 + 4) detail::ByteReader(data, 0, name).fail("cut short");
  detail::ByteReader in(data, bytes.size() - 4, name);  // the CRC after it
  if (crc32(data, bytes.size() - 4) != detail::ByteReader(data + bytes.size() - 4, 4, name).u32())
    in.fail("checksum mismatch");
  char magic[8];
  in.bytes(magic, 8);
  if (std::memcmp(magic, kSpillMagic, 8) != 0) in.fail("not a spill file");
  uint64_t blocks;
  in.bytes(&blocks, 8);
  constexpr size_t kMinBlock = sizeof(CellIndex) + sizeof(Words) + 4 + sizeof(MapBlock::Mask) + 4;
  if (blocks > in.remaining() / kMinBlock) in.fail("block count exceeds the file");
  NdtMap map(options);
  for (uint64_t b = 0; b < blocks; ++b) {
    CellIndex index;
    in.bytes(&index, sizeof index);
    auto block = std::make_unique<MapBlock>();
    Words known;
    in.bytes(known.data(), sizeof known);
    std::array<float, kBlockCells> values;
    in.bytes(values.data(), 4 * size_t(cellsIn(known)));
    int k = 0;
    forEachBit(known, [&](int i) {
      block->known.set(size_t(i));
      block->logodds[size_t(i)] = values[size_t(k++)];
    });
    in.bytes(block->has_stats.data(), sizeof block->has_stats);
    uint32_t count;
    in.bytes(&count, 4);
    size_t marked = 0;
    for (int w = 0; w < MapBlock::kWords; ++w) {
      marked += size_t(__builtin_popcountll(block->has_stats[size_t(w)]));
      if (block->has_stats[size_t(w)] & ~known[size_t(w)]) in.fail("statistics in an unknown cell");
    }
    if (block->known.none()) in.fail("an empty block");
    if (count != marked) in.fail("statistics count does not match its mask");
    if (count > in.remaining() / kStatsBytes) in.fail("statistics count exceeds the file");
    block->stats.resize(count);
    for (CellStats& s : block->stats) {
      in.bytes(&s.n, 4);
      in.bytes(s.relative_mean.data(), 3 * 8);
      in.bytes(s.scatter.data(), 9 * 8);
    }
    const size_t cells = block->known.count(), stats_bytes = statsBytes(block->stats);
    if (!MapInternals::grid(map).blocks().emplace(index, std::move(block)).second)
      in.fail("a block twice");
    MapInternals::countBlocks(map, cells, stats_bytes);
  }
  if (in.remaining() != 0) in.fail("bytes after the last block");
  MapInternals::touch(map);
  return map;
}

}  // namespace ndtom
