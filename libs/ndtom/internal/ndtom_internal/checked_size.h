// Size arithmetic on numbers read from files: every product and sum is checked, so a header
// claiming 2^64 / k elements of k bytes is caught instead of wrapping to a small size.
#pragma once

#include <cstdint>
#include <optional>
#include <string_view>

namespace ndtom {

/// a · b, or nullopt if it does not fit 64 bits.
inline std::optional<uint64_t> checkedMul(uint64_t a, uint64_t b) {
  uint64_t r;
  if (__builtin_mul_overflow(a, b, &r)) return std::nullopt;
  return r;
}

/// a + b, or nullopt if it does not fit 64 bits.
inline std::optional<uint64_t> checkedAdd(uint64_t a, uint64_t b) {
  uint64_t r;
  if (__builtin_add_overflow(a, b, &r)) return std::nullopt;
  return r;
}

/// True if count elements of `bytes_each` bytes fit in `available` bytes (no overflow).
inline bool fitsIn(uint64_t count, uint64_t bytes_each, uint64_t available) {
  const auto need = checkedMul(count, bytes_each);
  return need && *need <= available;
}

/// A decimal count: only digits, at most `max`; nullopt for a sign, a blank, an exponent or
/// anything larger (std::stoll would read "4294967297" whole, and a cast to int makes it 1).
inline std::optional<uint64_t> parseCount(std::string_view text, uint64_t max) {
  if (text.empty() || text.size() > 20) return std::nullopt;
  uint64_t value = 0;
  for (const char c : text) {
    if (c < '0' || c > '9') return std::nullopt;
    const auto shifted = checkedMul(value, 10);
    if (!shifted) return std::nullopt;
    const auto next = checkedAdd(*shifted, uint64_t(c - '0'));
    if (!next || *next > max) return std::nullopt;
    value = *next;
  }
  return value;
}

}  // namespace ndtom
