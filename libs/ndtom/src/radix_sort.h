// LSD radix sort on the low `key_bits` bits of a 64-bit key: a scan's ray ends are sorted in
// two or three linear passes instead of a comparison sort.
#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

#include "parallel.h"

namespace ndtom {

/// Stable sort of `items` (anything with a uint64_t `key`) using `buffer` as scratch, on up to
/// `threads` threads of `pool`: each counts and places a contiguous part, its items going after
/// those of the parts before it in every bucket, so the order does not depend on `threads`.
template <class T>
void radixSortByKey(std::vector<T>& items, std::vector<T>& buffer, int key_bits, WorkerPool& pool,
                    size_t threads) {
  // As few passes as digits of at most 13 bits allow (64 KiB of counters per thread, in L2).
  constexpr int kMaxDigitBits = 13;
  const int passes = std::max(1, (key_bits + kMaxDigitBits - 1) / kMaxDigitBits);
  const int digit_bits = (key_bits + passes - 1) / passes;
  const uint64_t mask = (uint64_t(1) << digit_bits) - 1;
  const size_t buckets = size_t(1) << digit_bits, n = items.size();
  threads = std::max<size_t>(1, std::min(threads, n));
  buffer.resize(n);
  std::vector<size_t> start(threads * buckets);  // [thread * buckets + digit]
  for (int shift = 0; shift < key_bits; shift += digit_bits) {
    pool.run(threads, [&](size_t t) {
      size_t* count = &start[t * buckets];
      std::fill(count, count + buckets, size_t(0));
      const auto [begin, end] = partRange(n, threads, t);
      for (size_t i = begin; i < end; ++i) ++count[(items[i].key >> shift) & mask];
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
      for (size_t i = begin; i < end; ++i)
        buffer[next[(items[i].key >> shift) & mask]++] = items[i];
    });
    items.swap(buffer);
  }
}

}  // namespace ndtom
