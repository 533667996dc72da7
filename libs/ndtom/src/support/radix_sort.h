// LSD radix sort of 64-bit words on one bit field: a scan's ray ends (cell key and point
// index packed in a word) are sorted in two or three linear passes instead of a comparison sort.
#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

#include "support/parallel.h"

namespace ndtom {

/// Stable sort of `words` by bits [low_bit, low_bit + key_bits) (those above are zero, or
/// sorted on as well; low_bit + key_bits <= 64), using `buffer` as scratch,
/// on up to `threads` threads of `pool`: each counts and places a contiguous part, its words
/// going after those of the parts before it in every bucket, so the order does not depend on
/// `threads`. Words are 8 bytes, not a 16-byte key and index pair: the passes stream half as
/// much memory, which is what they wait for.
inline void radixSortByBits(std::vector<uint64_t>& words, std::vector<uint64_t>& buffer,
                            int low_bit, int key_bits, WorkerPool& pool, size_t threads) {
  // As few passes as digits of at most 13 bits allow (64 KiB of counters per thread, in L2).
  constexpr int kMaxDigitBits = 13;
  const int passes = std::max(1, (key_bits + kMaxDigitBits - 1) / kMaxDigitBits);
  const int digit_bits = (key_bits + passes - 1) / passes;
  const uint64_t mask = (uint64_t(1) << digit_bits) - 1;
  const size_t buckets = size_t(1) << digit_bits, n = words.size();
  threads = std::max<size_t>(1, std::min(threads, n));
  buffer.resize(n);
  std::vector<size_t> start(threads * buckets);  // [thread * buckets + digit]
  for (int shift = low_bit; shift < low_bit + key_bits; shift += digit_bits) {
    pool.run(threads, [&](size_t t) {
      size_t* count = &start[t * buckets];
      std::fill(count, count + buckets, size_t(0));
      const auto [begin, end] = partRange(n, threads, t);
      for (size_t i = begin; i < end; ++i) ++count[(words[i] >> shift) & mask];
    });
    size_t sum = 0;
    for (size_t digit = 0; digit < buckets; ++digit)
      for (size_t t = 0; t < threads; ++t) {
        const size_t count = start[t * buckets + digit];
        start[t * buckets + digit] = sum;
        sum += count;
      }
    pool.run(threads, [&](size_t t) {
      size_t* next = &start[t * buckets];
      const auto [begin, end] = partRange(n, threads, t);
      for (size_t i = begin; i < end; ++i) buffer[next[(words[i] >> shift) & mask]++] = words[i];
    });
    words.swap(buffer);
  }
}

}  // namespace ndtom
