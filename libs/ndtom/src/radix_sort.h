// LSD radix sort on the low `key_bits` bits of a 64-bit key: a scan's ray ends are sorted in
// two or three linear passes instead of a comparison sort.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

namespace ndtom {

/// Stable sort of `items` (anything with a uint64_t `key`) using `buffer` as scratch.
template <class T>
void radixSortByKey(std::vector<T>& items, std::vector<T>& buffer, int key_bits) {
  constexpr int kDigitBits = 11;
  constexpr size_t kBuckets = size_t(1) << kDigitBits;
  buffer.resize(items.size());
  for (int shift = 0; shift < key_bits; shift += kDigitBits) {
    std::array<size_t, kBuckets> start{};
    for (const T& item : items) ++start[(item.key >> shift) & (kBuckets - 1)];
    size_t sum = 0;
    for (size_t& s : start) {
      const size_t count = s;
      s = sum;
      sum += count;
    }
    for (const T& item : items) buffer[start[(item.key >> shift) & (kBuckets - 1)]++] = item;
    items.swap(buffer);
  }
}

}  // namespace ndtom
