#include "partition/count_message.h"

#include <stdexcept>

namespace ndtom {

namespace {
constexpr size_t kBlockHeaderWords = 4;
}

void appendCountBlock(const CellIndex& block, const uint32_t* counts,
                      std::vector<uint32_t>& words) {
  const size_t header = words.size();
  words.insert(words.end(), {uint32_t(block.x), uint32_t(block.y), uint32_t(block.z), 0});
  uint32_t n = 0;
  for (uint32_t i = 0; i < uint32_t(kBlockCells); ++i) {
    if (counts[i] == 0) continue;
    words.push_back(i);
    words.push_back(counts[i]);
    ++n;
  }
  words[header + 3] = n;
}

void addCountMessage(const std::vector<uint32_t>& words, const TileOwnership& owned,
                     const std::function<uint32_t*(const CellIndex& block)>& countsOf) {
  auto malformed = [] {
    return std::runtime_error("insertScanPart: a malformed message of counts from another process");
  };
  for (size_t at = 0; at < words.size();) {
    if (words.size() - at < kBlockHeaderWords) throw malformed();
    const CellIndex b{int32_t(words[at]), int32_t(words[at + 1]), int32_t(words[at + 2])};
    const size_t n = words[at + 3];
    at += kBlockHeaderWords;
    if (!owned.ownsBlock(b) || n > size_t(kBlockCells) || (words.size() - at) / 2 < n)
      throw malformed();
    uint32_t* counts = countsOf(b);
    for (size_t k = 0; k < n; ++k, at += 2) {
      if (words[at] >= uint32_t(kBlockCells)) throw malformed();
      counts[words[at]] += words[at + 1];
    }
  }
}

}  // namespace ndtom
