// LSD radix sort on the low `key_bits` bits of a 64-bit key: a scan's ray ends are sorted in
// two or three linear passes instead of a comparison sort.
#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

namespace ndtom {

/// Stable sort of `items` (anything with a uint64_t `key`) using `buffer` as scratch.
template <class T>
void radixSortByKey(std::vector<T>& items, std::vector<T>& buffer, int key_bits) {
  // As few passes as digits of at most 13 bits allow (64 KiB of counters, in L2).
  constexpr int kMaxDigitBits = 13;
  const int passes = std::max(1, (key_bits + kMaxDigitBits - 1) / kMaxDigitBits);
  const int digit_bits = (key_bits + passes - 1) / passes;
  const uint64_t mask = (uint64_t(1) << digit_bits) - 1;
  buffer.resize(items.size());
  std::vector<size_t> start(size_t(1) << digit_bits);
  for (int shift = 0; shift < key_bits; shift += digit_bits) {
    std::fill(start.begin(), start.end(), size_t(0));
    for (const T& item : items) ++start[(item.key >> shift) & mask];
    size_t sum = 0;
    for (size_t& s : start) {
      const size_t count = s;
      s = sum;
      sum += count;
    }
    for (const T& item : items) buffer[start[(item.key >> shift) & mask]++] = item;
    items.swap(buffer);
  }
}

}  // namespace ndtom
