// Version 2 of the cell section (layout in map_io.h): most known cells are free space whose
// log-odds take a handful of values (the same clamped updates, repeated), so cells are
// located by per-block presence masks instead of per-cell keys, log-odds go through a
// dictionary with runs in block order, and only cells with statistics pay for them. Exact:
// every value is stored with its bits.
#include <algorithm>
#include <array>
#include <unordered_map>

#include "files/map_codec.h"
#include "ndtom_internal/checked_size.h"

namespace ndtom::detail {
namespace {

enum LogOddsCoding : uint8_t { kDictionary = 0, kRaw = 1 };

constexpr int kMaskBytes = kBlockCells / 8;
// The fewest bytes a block takes: 3 one-byte coordinate deltas, the u64 byte mask, one mask
// byte, the statistics count (log-odds in a run started before take none).
constexpr uint64_t kMinBlockBytes = 3 + 8 + 1 + 1;
// Blocks holding a supported cell (|i| < 2^30): [-2^27, 2^27 - 1] on each axis.
constexpr int64_t kMaxBlock = int64_t(kMaxCellIndex) >> kBlockLog2;

uint64_t zigzag(int64_t v) {
  return (uint64_t(v) << 1) ^ uint64_t(v >> 63);
}
int64_t unzigzag(uint64_t u) {
  return int64_t(u >> 1) ^ -int64_t(u & 1);
}

uint32_t bitsOf(float v) {
  uint32_t u;
  std::memcpy(&u, &v, 4);
  return u;
}

/// f(block, cells of the block in offset order) for every block, in ascending block order.
template <class F>
void forEachBlock(const NdtMap& map, F&& f) {
  std::vector<CellView> cells;
  cells.reserve(kBlockCells);
  CellIndex block;
  map.forEachCellOrdered([&](const CellView& c) {
    const CellIndex b = blockOf(c.index);
    if (!cells.empty() && b != block) {
      f(block, cells);
      cells.clear();
    }
    block = b;
    cells.push_back(c);
  });
  if (!cells.empty()) f(block, cells);
}

struct Run {
  uint32_t value;   ///< bits of the log-odds, then its dictionary index
  uint64_t length;  ///< cells
};

/// How the log-odds are coded: the dictionary (most used first) and the runs through it, or
/// raw floats when those would take fewer bytes (values that rarely repeat).
struct LogOddsPlan {
  LogOddsCoding coding = kDictionary;
  std::vector<uint32_t> dictionary;
  std::vector<Run> runs;
  uint64_t blocks = 0;
};

LogOddsPlan planLogOdds(const NdtMap& map) {
  LogOddsPlan plan;
  CellIndex last_block;
  map.forEachCellOrdered([&](const CellView& c) {
    const CellIndex b = blockOf(c.index);
    if (plan.blocks == 0 || b != last_block) ++plan.blocks;
    last_block = b;
    const uint32_t bits = bitsOf(c.logodds);
    if (!plan.runs.empty() && plan.runs.back().value == bits)
      ++plan.runs.back().length;
    else
      plan.runs.push_back({bits, 1});
  });
  std::unordered_map<uint32_t, uint64_t> uses;
  for (const Run& r : plan.runs) ++uses[r.value];
  std::vector<std::pair<uint32_t, uint64_t>> order(uses.begin(), uses.end());
  std::sort(order.begin(), order.end(), [](const auto& a, const auto& b) {
    return a.second != b.second ? a.second > b.second : a.first < b.first;
  });
  std::unordered_map<uint32_t, uint32_t> index_of;
  for (const auto& [bits, count] : order) {
    index_of.emplace(bits, uint32_t(plan.dictionary.size()));
    plan.dictionary.push_back(bits);
  }
  uint64_t dictionary_bytes = varintSize(order.size()) + 4 * order.size();
  for (Run& r : plan.runs) {
    r.value = index_of.at(r.value);
    dictionary_bytes += varintSize(2 * uint64_t(r.value) + 1);
    if (r.length > 1) dictionary_bytes += varintSize(r.length - 2);
  }
  if (dictionary_bytes > 4 * uint64_t(map.numCells())) plan.coding = kRaw;
  return plan;
}

/// The block's 512-bit cell mask as a u64 telling which of its 64 bytes are non-zero, then
/// those bytes: a surface crossing a block fills few of them.
void writeMask(ByteWriter& out, const std::vector<CellView>& cells) {
  std::array<uint8_t, kMaskBytes> mask{};
  for (const CellView& c : cells) {
    const int i = offsetInBlock(c.index);
    mask[size_t(i >> 3)] |= uint8_t(1u << (i & 7));
  }
  uint64_t nonzero = 0;
  for (int j = 0; j < kMaskBytes; ++j) nonzero |= uint64_t(mask[size_t(j)] != 0) << j;
  out.u64(nonzero);
  for (const uint8_t byte : mask)
    if (byte) out.u8(byte);
}

/// varint(2N + s), s = 1 if the scatter follows; mean and scatter as raw f64 bits. A zero
/// scatter (every cell of one point, repeated points) is left out.
void writeStats(ByteWriter& out, const CellStats& s) {
  const Eigen::Matrix3d& m = s.scatter;
  const double upper[6] = {m(0, 0), m(0, 1), m(0, 2), m(1, 1), m(1, 2), m(2, 2)};
  uint64_t any = 0;  // bits, not values: -0.0 is kept
  for (const double v : upper) {
    uint64_t u;
    std::memcpy(&u, &v, 8);
    any |= u;
  }
  const bool zero = any == 0;
  out.varint(2 * uint64_t(s.n) + (zero ? 0 : 1));
  for (int a = 0; a < 3; ++a) out.f64(s.relative_mean[a]);
  if (!zero)
    for (const double v : upper) out.f64(v);
}

CellStats readStats(ByteReader& in) {
  const uint64_t head = in.varint();
  const uint64_t n = head >> 1;
  if (n == 0 || n > kMaxCellPoints) in.fail("point count " + std::to_string(n) + " out of range");
  CellStats s;
  s.n = uint32_t(n);
  for (int a = 0; a < 3; ++a) s.relative_mean[a] = in.f64();
  if (head & 1) s.scatter = readScatter(in);
  return s;
}

/// The offsets of a block's known cells, ascending, from its mask.
int readMask(ByteReader& in, std::array<int, kBlockCells>& offsets) {
  const uint64_t nonzero = in.u64();
  if (nonzero == 0) in.fail("empty block");
  int k = 0;
  for (int j = 0; j < kMaskBytes; ++j) {
    if (!((nonzero >> j) & 1)) continue;
    const uint8_t byte = in.u8();
    if (byte == 0) in.fail("zero byte in a block mask");
    for (int bit = 0; bit < 8; ++bit)
      if ((byte >> bit) & 1) offsets[size_t(k++)] = 8 * j + bit;
  }
  return k;
}

/// The next block's coordinates: the previous ones plus zigzag deltas, in range and ascending.
CellIndex readBlockIndex(ByteReader& in, const CellIndex& previous, bool first) {
  CellIndex block;
  for (int a = 0; a < 3; ++a) {
    const int64_t delta = unzigzag(in.varint());
    if (delta < -2 * kMaxBlock || delta > 2 * kMaxBlock) in.fail("block coordinate out of range");
    const int64_t v = int64_t(previous[a]) + delta;
    if (v < -kMaxBlock || v >= kMaxBlock) in.fail("block coordinate out of range");
    block[a] = int32_t(v);
  }
  if (!first && !(previous < block)) in.fail("blocks out of order");
  return block;
}

/// Hands out the log-odds of consecutive cells, reading a run header when one is used up.
class LogOddsReader {
 public:
  LogOddsReader(ByteReader& in, uint64_t cells) : in_(in), cells_(cells) {
    coding_ = in.u8();
    if (coding_ != kDictionary && coding_ != kRaw) in.fail("unknown log-odds coding");
    if (coding_ == kRaw) return;
    const uint64_t size = in.varint();
    if (in.remaining() < 4 || !fitsIn(size, 4, in.remaining() - 4))
      in.fail("dictionary size " + std::to_string(size) + " exceeds the file size");
    dictionary_.resize(size_t(size));
    for (float& v : dictionary_) v = in.f32();
  }
  /// Log-odds of cell number `cell` (counted from the first of the file).
  float next(uint64_t cell) {
    if (coding_ == kRaw) return in_.f32();
    if (left_ == 0) {
      const uint64_t head = in_.varint();  // 2 · index + (longer than one cell)
      if ((head >> 1) >= dictionary_.size()) in_.fail("dictionary index out of range");
      value_ = dictionary_[size_t(head >> 1)];
      left_ = 1;
      if (head & 1) {
        const uint64_t extra = in_.varint();  // the run's length minus two
        if (extra >= cells_ - cell - 1) in_.fail("run longer than the cells left");
        left_ = extra + 2;
      }
    }
    --left_;
    return value_;
  }

 private:
  ByteReader& in_;
  uint64_t cells_;
  uint8_t coding_ = kRaw;
  std::vector<float> dictionary_;
  float value_ = 0;
  uint64_t left_ = 0;
};

}  // namespace

void encodeBlocks(const NdtMap& map, ByteWriter& out) {
  const LogOddsPlan plan = planLogOdds(map);
  out.u64(map.numCells());
  out.u64(plan.blocks);
  out.u8(plan.coding);
  if (plan.coding == kDictionary) {
    out.varint(plan.dictionary.size());
    for (const uint32_t bits : plan.dictionary) out.u32(bits);
  }
  size_t run = 0;
  uint64_t left = 0;  // cells of the current run still to write
  CellIndex previous;
  forEachBlock(map, [&](const CellIndex& block, const std::vector<CellView>& cells) {
    for (int a = 0; a < 3; ++a) out.varint(zigzag(int64_t(block[a]) - int64_t(previous[a])));
    previous = block;
    writeMask(out, cells);
    for (const CellView& c : cells) {
      if (plan.coding == kRaw) {
        out.f32(c.logodds);
        continue;
      }
      if (left == 0) {  // a run header where its first cell is
        const Run& r = plan.runs[run++];
        // Most runs are one cell long: their header is the index alone.
        out.varint(2 * uint64_t(r.value) + (r.length > 1));
        if (r.length > 1) out.varint(r.length - 2);
        left = r.length;
      }
      --left;
    }
    // Which of the block's known cells have statistics: a count, then a bit per known cell.
    std::array<uint8_t, kMaskBytes> has{};
    uint64_t count = 0;
    for (size_t j = 0; j < cells.size(); ++j)
      if (cells[j].stats && cells[j].stats->n > 0) {
        has[j >> 3] |= uint8_t(1u << (j & 7));
        ++count;
      }
    out.varint(count);
    if (count > 0) out.bytes(has.data(), (cells.size() + 7) / 8);
    for (const CellView& c : cells)
      if (c.stats && c.stats->n > 0) writeStats(out, *c.stats);
    out.maybeFlush();
  });
}

void decodeBlocks(ByteReader& in, NdtMap& map) {
  const uint64_t cells = in.u64();
  const uint64_t blocks = in.u64();
  // Counts checked against the bytes left before anything is read or allocated for them.
  if (in.remaining() < 4 || !fitsIn(blocks, kMinBlockBytes, in.remaining() - 4))
    in.fail("block count " + std::to_string(blocks) + " exceeds the file size");
  if (cells > blocks * kBlockCells)
    in.fail("cell count " + std::to_string(cells) + " exceeds its blocks");
  LogOddsReader logodds(in, cells);
  uint64_t decoded = 0;
  CellIndex block;
  std::array<int, kBlockCells> offsets;
  std::array<float, kBlockCells> values;
  std::array<uint8_t, kMaskBytes> has;
  for (uint64_t b = 0; b < blocks; ++b) {
    block = readBlockIndex(in, block, b == 0);
    const int k = readMask(in, offsets);
    if (uint64_t(k) > cells - decoded) in.fail("more cells than the cell count");
    for (int j = 0; j < k; ++j) values[size_t(j)] = logodds.next(decoded + uint64_t(j));
    const uint64_t count = in.varint();
    if (count > uint64_t(k)) in.fail("more statistics than cells in a block");
    has.fill(0);
    if (count > 0) in.bytes(has.data(), size_t(k + 7) / 8);
    uint64_t marked = 0;
    for (const uint8_t byte : has) marked += uint64_t(__builtin_popcount(byte));
    if (marked != count || (k % 8 && (has[size_t(k / 8)] >> (k % 8))))
      in.fail("statistics mask does not match its count");
    for (int j = 0; j < k; ++j) {
      const bool stats = (has[size_t(j >> 3)] >> (j & 7)) & 1;
      setDecodedCell(in, map, cellInBlock(block, offsets[size_t(j)]), values[size_t(j)],
                     stats ? readStats(in) : CellStats{}, cells);
    }
    decoded += uint64_t(k);
  }
  if (decoded != cells) in.fail("cell count does not match the blocks");
}

}  // namespace ndtom::detail
