#include "partition/count_message.h"

#include <cstring>
#include <stdexcept>

namespace ndtom {

namespace {
constexpr size_t kPointCountWords = 6;
constexpr size_t kHeadWords = kPointCountWords + 1;
constexpr size_t kWordsPerHit = 6;
constexpr size_t kBlockHeaderWords = 4;
}  // namespace

std::runtime_error malformedMessage() {
  return std::runtime_error("insertScanPart: a malformed message from another process");
}

void appendMessageHead(const InsertionReport& counts, const Eigen::Vector3d* hits, size_t n,
                       std::vector<uint32_t>& words) {
  words.insert(words.end(),
               {uint32_t(counts.hits), uint32_t(counts.truncated),
                uint32_t(counts.rejected_non_finite), uint32_t(counts.rejected_too_close),
                uint32_t(counts.rejected_out_of_grid), uint32_t(counts.rejected_too_far),
                uint32_t(n)});
  const size_t at = words.size();
  words.resize(at + n * kWordsPerHit);
  if (n > 0) std::memcpy(&words[at], hits, n * sizeof(Eigen::Vector3d));
  static_assert(sizeof(Eigen::Vector3d) == kWordsPerHit * sizeof(uint32_t));
}

size_t readMessageHead(const std::vector<uint32_t>& words, const TileOwnership& owned,
                       const GridGeometry& geometry, InsertionReport& counts,
                       std::vector<Eigen::Vector3d>& hits) {
  if (words.size() < kHeadWords) throw malformedMessage();
  counts.hits += words[0];
  counts.truncated += words[1];
  counts.rejected_non_finite += words[2];
  counts.rejected_too_close += words[3];
  counts.rejected_out_of_grid += words[4];
  counts.rejected_too_far += words[5];
  const size_t n = words[kPointCountWords];
  if ((words.size() - kHeadWords) / kWordsPerHit < n) throw malformedMessage();
  const size_t first = hits.size();
  hits.resize(first + n);
  if (n > 0) std::memcpy(hits[first].data(), &words[kHeadWords], n * sizeof(Eigen::Vector3d));
  for (size_t i = first; i < hits.size(); ++i)
    if (!geometry.inRange(hits[i]) || !owned.ownsBlock(blockOf(geometry.cellOf(hits[i]))))
      throw malformedMessage();
  return kHeadWords + n * kWordsPerHit;
}

void appendCountBlock(const CellIndex& block, const uint32_t* counts,
                      std::vector<uint32_t>& words) {
  // A far block holds a few rays' cells of its 512. Counting them first (a loop the compiler
  // vectorizes) sizes the message exactly; the pairs are then written four cells at a time,
  // skipping empty fours, without a capacity check per cell.
  uint32_t n = 0;
  for (int i = 0; i < kBlockCells; ++i) n += counts[i] != 0;
  const size_t header = words.size();
  words.resize(header + kBlockHeaderWords + 2 * size_t(n));
  uint32_t* out = &words[header];
  out[0] = uint32_t(block.x);
  out[1] = uint32_t(block.y);
  out[2] = uint32_t(block.z);
  out[3] = n;
  uint32_t* pair = out + kBlockHeaderWords;
  static_assert(kBlockCells % 4 == 0);
  for (uint32_t i = 0; i < uint32_t(kBlockCells); i += 4) {
    if ((counts[i] | counts[i + 1] | counts[i + 2] | counts[i + 3]) == 0) continue;
    for (uint32_t k = i; k < i + 4; ++k) {
      if (counts[k] == 0) continue;
      *pair++ = k;
      *pair++ = counts[k];
    }
  }
}

void addCountMessage(const std::vector<uint32_t>& words, size_t at, const TileOwnership& owned,
                     const std::function<uint32_t*(const CellIndex& block)>& countsOf) {
  while (at < words.size()) {
    if (words.size() - at < kBlockHeaderWords) throw malformedMessage();
    const CellIndex b{int32_t(words[at]), int32_t(words[at + 1]), int32_t(words[at + 2])};
    const size_t n = words[at + 3];
    at += kBlockHeaderWords;
    if (!owned.ownsBlock(b) || n > size_t(kBlockCells) || (words.size() - at) / 2 < n)
      throw malformedMessage();
    uint32_t* counts = countsOf(b);
    for (size_t k = 0; k < n; ++k, at += 2) {
      if (words[at] >= uint32_t(kBlockCells)) throw malformedMessage();
      counts[words[at]] += words[at + 1];
    }
  }
}

}  // namespace ndtom
