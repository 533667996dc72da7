// LSD radix sort of 64-bit words on one bit field: a scan's ray ends (cell key and point
// index packed in a word) are sorted in two or three linear passes instead of a comparison sort.
#pragma once

#include <algorithm>
#include <cstdint>
#include <memory>
#include <vector>

#include "support/parallel.h"

namespace ndtom {

/// Stable sort of `words` by bits [low_bit, low_bit + key_bits) (those above are zero, or
/// sorted on as well; low_bit + key_bits <= 64), using `buffer` as scratch,
/// on up to `threads` threads of `pool`: each counts and places a contiguous part, its words
/// going after those of the parts before it in every bucket, so the order does not depend on
/// `threads`. Words are 8 bytes, not a 16-byte key and index pair: the passes stream half as
/// much memory, which is what they wait for.
/// Turns the counts `start[thread * buckets + digit]` into where each thread's words of each
/// digit go: digits in order, threads in order within a digit. Over a few threads in one pass;
/// with many, a pass over buckets × threads counters would be the sort's serial bottleneck, so
/// threads take ranges of digits.
inline void startOffsets(size_t* start, size_t buckets, size_t threads, WorkerPool& pool) {
  const auto offsets = [&](size_t first_digit, size_t end_digit, size_t sum) {
    for (size_t digit = first_digit; digit < end_digit; ++digit)
      for (size_t t = 0; t < threads; ++t) {
        const size_t count = start[t * buckets + digit];
        start[t * buckets + digit] = sum;
        sum += count;
      }
  };
  constexpr size_t kSerialUpTo = size_t(1) << 15;  // counters: two threads of 13-bit digits
  if (buckets * threads <= kSerialUpTo) return offsets(0, buckets, 0);
  std::vector<size_t> before(threads + 1, 0);  // words in the digit ranges before range t
  pool.run(threads, [&](size_t r) {
    const auto [first_digit, end_digit] = partRange(buckets, threads, r);
    size_t sum = 0;
    for (size_t digit = first_digit; digit < end_digit; ++digit)
      for (size_t t = 0; t < threads; ++t) sum += start[t * buckets + digit];
    before[r + 1] = sum;
  });
  for (size_t r = 0; r < threads; ++r) before[r + 1] += before[r];
  pool.run(threads, [&](size_t r) {
    const auto [first_digit, end_digit] = partRange(buckets, threads, r);
    offsets(first_digit, end_digit, before[r]);
  });
}

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
  // [thread * buckets + digit]; not zeroed here: each thread clears its own counters, and at
  // 16 threads they are a megabyte.
  const std::unique_ptr<size_t[]> start(new size_t[threads * buckets]);
  for (int shift = low_bit; shift < low_bit + key_bits; shift += digit_bits) {
    pool.run(threads, [&](size_t t) {
      size_t* count = &start[t * buckets];
      std::fill(count, count + buckets, size_t(0));
      const auto [begin, end] = partRange(n, threads, t);
      for (size_t i = begin; i < end; ++i) ++count[(words[i] >> shift) & mask];
    });
    startOffsets(start.get(), buckets, threads, pool);
    pool.run(threads, [&](size_t t) {
      size_t* next = &start[t * buckets];
      const auto [begin, end] = partRange(n, threads, t);
      for (size_t i = begin; i < end; ++i) buffer[next[(words[i] >> shift) & mask]++] = words[i];
    });
    words.swap(buffer);
  }
}

}  // namespace ndtom
