#include "spill_codec.h"

#include <array>
#include <bitset>
#include <cstring>

#include "map_block.h"
#include "ndtom_internal/crc32.h"

namespace ndtom {
namespace {

constexpr char kMagic[8] = {'N', 'D', 'T', 'O', 'M', 'S', 'P', 'L'};
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

class Reader {
 public:
  Reader(const std::string& bytes, const std::string& source) : bytes_(bytes), source_(source) {}
  void take(void* to, size_t n) {
    if (n > bytes_.size() - 4 - at_) fail("cut short");
    std::memcpy(to, bytes_.data() + at_, n);
    at_ += n;
  }
  template <class T>
  T get() {
    T v;
    take(&v, sizeof v);
    return v;
  }
  size_t left() const { return bytes_.size() - 4 - at_; }
  [[noreturn]] void fail(const std::string& what) const {
    throw MapFormatError("spill file " + source_ + ": " + what);
  }

 private:
  const std::string& bytes_;
  const std::string& source_;
  size_t at_ = 0;
};

}  // namespace

void SpillCodec::write(const NdtMap& map, const MapByteSink& sink) {
  std::string out(kMagic, sizeof kMagic);
  auto put = [&](const void* p, size_t n) { out.append(static_cast<const char*>(p), n); };
  // Blocks without a known cell (insertion can leave some) are not part of the map: dropped.
  uint64_t blocks = 0;
  for (const auto& entry : map.grid_.blocks()) blocks += entry.second->known.any();
  put(&blocks, 8);
  for (const auto& [index, block] : map.grid_.blocks()) {
    if (block->known.none()) continue;
    put(&index, sizeof index);
    const Words known = wordsOf(block->known);
    put(known.data(), sizeof known);
    std::array<float, kBlockCells> values;
    int k = 0;
    const auto& logodds = block->logodds;  // a structured binding cannot be captured in C++17
    forEachBit(known, [&](int i) { values[size_t(k++)] = logodds[size_t(i)]; });
    put(values.data(), 4 * size_t(k));
    put(block->has_stats.data(), sizeof block->has_stats);
    const uint32_t count = uint32_t(block->stats.size());
    put(&count, 4);
    for (const CellStats& s : block->stats) {
      put(&s.n, 4);
      put(s.relative_mean.data(), 3 * 8);
      put(s.scatter.data(), 9 * 8);
    }
  }
  const uint32_t crc = crc32(out.data(), out.size());
  put(&crc, 4);
  sink(reinterpret_cast<const uint8_t*>(out.data()), out.size());
}

NdtMap SpillCodec::read(const std::string& bytes, const MapOptions& options,
                        const std::string& source) {
  Reader in(bytes, source);
  if (bytes.size() < sizeof kMagic + 8 + 4) in.fail("cut short");
  uint32_t stored_crc;
  std::memcpy(&stored_crc, bytes.data() + bytes.size() - 4, 4);
  if (crc32(bytes.data(), bytes.size() - 4) != stored_crc) in.fail("checksum mismatch");
  char magic[8];
  in.take(magic, 8);
  if (std::memcmp(magic, kMagic, 8) != 0) in.fail("not a spill file");
  const uint64_t blocks = in.get<uint64_t>();
  constexpr size_t kMinBlock = sizeof(CellIndex) + sizeof(Words) + 4 + sizeof(MapBlock::Mask) + 4;
  if (blocks > in.left() / kMinBlock) in.fail("block count exceeds the file");
  NdtMap map(options);
  for (uint64_t b = 0; b < blocks; ++b) {
    const CellIndex index = in.get<CellIndex>();
    auto block = std::make_unique<MapBlock>();
    Words known;
    in.take(known.data(), sizeof known);
    std::array<float, kBlockCells> values;
    in.take(values.data(), 4 * size_t(cellsIn(known)));
    int k = 0;
    forEachBit(known, [&](int i) {
      block->known.set(size_t(i));
      block->logodds[size_t(i)] = values[size_t(k++)];
    });
    in.take(block->has_stats.data(), sizeof block->has_stats);
    const uint32_t count = in.get<uint32_t>();
    size_t marked = 0;
    for (int w = 0; w < MapBlock::kWords; ++w) {
      marked += size_t(__builtin_popcountll(block->has_stats[size_t(w)]));
      for (int bit = 0; bit < 64; ++bit)
        if ((block->has_stats[size_t(w)] >> bit & 1) && !block->known[size_t(64 * w + bit)])
          in.fail("statistics in an unknown cell");
    }
    if (block->known.none()) in.fail("an empty block");
    if (count != marked) in.fail("statistics count does not match its mask");
    if (count > in.left() / kStatsBytes) in.fail("statistics count exceeds the file");
    block->stats.resize(count);
    for (CellStats& s : block->stats) {
      s.n = in.get<uint32_t>();
      in.take(s.relative_mean.data(), 3 * 8);
      in.take(s.scatter.data(), 9 * 8);
    }
    const size_t cells = block->known.count(), stats_bytes = statsBytes(block->stats);
    if (!map.grid_.blocks().emplace(index, std::move(block)).second) in.fail("a block twice");
    map.num_cells_ += cells;
    map.stats_bytes_ += stats_bytes;
  }
  if (in.left() != 0) in.fail("bytes after the last block");
  map.touch();
  return map;
}

}  // namespace ndtom
