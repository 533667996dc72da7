// Little-endian writing and bounds-checked reading of the map file's fields (map_io.cpp and
// the cell codecs). The writer hands its buffer over in chunks with a running CRC, so a map
// of any size is encoded through about 1 MB of memory.
#pragma once

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "ndtom/files/map_io.h"
#include "ndtom_internal/crc32.h"

namespace ndtom::detail {

class ByteWriter {
 public:
  static constexpr size_t kChunk = size_t(1) << 20;
  explicit ByteWriter(const MapByteSink& sink) : sink_(sink), out_(kChunk + 4096) {}
  void bytes(const void* p, size_t n) {
    if (n > 0) std::memcpy(room(n), p, n);
  }
  /// Hands over what is buffered if it is a chunk or more.
  void maybeFlush() {
    if (used_ >= kChunk) flush();
  }
  void flush() {
    crc_ = crc32(out_.data(), used_, crc_);
    sink_(out_.data(), used_);
    used_ = 0;
  }
  /// Appends the CRC of everything written and hands the rest over.
  void finish() {
    const uint32_t crc = crc32(out_.data(), used_, crc_);
    u32(crc);
    sink_(out_.data(), used_);
    used_ = 0;
  }
  // Into a buffer with a room check per field, not a push_back per byte: encoding a map is
  // mostly these.
  void u8(uint8_t v) { *room(1) = v; }
  void u32(uint32_t v) {
    uint8_t* at = room(4);
    for (int i = 0; i < 4; ++i) at[i] = uint8_t(v >> (8 * i));
  }
  void u64(uint64_t v) {
    uint8_t* at = room(8);
    for (int i = 0; i < 8; ++i) at[i] = uint8_t(v >> (8 * i));
  }
  /// LEB128: 7 bits a byte, low first; small counts take one byte.
  void varint(uint64_t v) {
    uint8_t* at = room(kMaxVarintBytes);
    size_t n = 0;
    while (v >= 0x80) {
      at[n++] = uint8_t(v | 0x80);
      v >>= 7;
    }
    at[n++] = uint8_t(v);
    used_ -= kMaxVarintBytes - n;
  }
  void f32(float v) {
    uint32_t u;
    std::memcpy(&u, &v, 4);
    u32(u);
  }
  void f64(double v) {
    uint64_t u;
    std::memcpy(&u, &v, 8);
    u64(u);
  }

 private:
  static constexpr size_t kMaxVarintBytes = 10;
  /// Where the next `n` bytes go; they count as written.
  uint8_t* room(size_t n) {
    if (__builtin_expect(n > out_.size() - used_, 0)) out_.resize(std::max(2 * out_.size(), used_ + n));
    uint8_t* at = out_.data() + used_;
    used_ += n;
    return at;
  }

  const MapByteSink& sink_;
  std::vector<uint8_t> out_;  ///< its first used_ bytes are written
  size_t used_ = 0;
  uint32_t crc_ = 0;
};

/// Bytes of varint(v).
inline size_t varintSize(uint64_t v) {
  size_t n = 1;
  while (v >= 0x80) v >>= 7, ++n;
  return n;
}

/// Every read checks the bytes left and throws MapFormatError naming the source and offset.
class ByteReader {
 public:
  ByteReader(const uint8_t* data, size_t size, const std::string& source)
      : data_(data), size_(size), source_(source) {}

  size_t remaining() const { return size_ - pos_; }
  size_t position() const { return pos_; }
  const std::string& source() const { return source_; }
  [[noreturn]] void fail(const std::string& why) const {
    throw MapFormatError(source_ + ": " + why + " (at byte " + std::to_string(pos_) + ")");
  }
  void need(size_t n) const {
    if (remaining() < n) fail("truncated");
  }
  void bytes(void* p, size_t n) {
    need(n);
    std::memcpy(p, data_ + pos_, n);
    pos_ += n;
  }
  uint8_t u8() {
    need(1);
    return data_[pos_++];
  }
  uint32_t u32() {
    need(4);
    uint32_t v = 0;
    for (int i = 0; i < 4; ++i) v |= uint32_t(data_[pos_ + i]) << (8 * i);
    pos_ += 4;
    return v;
  }
  uint64_t u64() {
    need(8);
    uint64_t v = 0;
    for (int i = 0; i < 8; ++i) v |= uint64_t(data_[pos_ + i]) << (8 * i);
    pos_ += 8;
    return v;
  }
  /// At most 10 bytes, and no bits beyond 64.
  uint64_t varint() {
    uint64_t v = 0;
    for (int shift = 0;; shift += 7) {
      const uint8_t b = u8();
      if (shift == 63 && b > 1) fail("varint overflows 64 bits");
      v |= uint64_t(b & 0x7F) << shift;
      if (!(b & 0x80)) return v;
    }
  }
  int32_t i32() { return int32_t(u32()); }
  float f32() {
    const uint32_t u = u32();
    float v;
    std::memcpy(&v, &u, 4);
    return v;
  }
  double f64() {
    const uint64_t u = u64();
    double v;
    std::memcpy(&v, &u, 8);
    return v;
  }

 private:
  const uint8_t* data_;
  size_t size_;
  size_t pos_ = 0;
  std::string source_;
};

}  // namespace ndtom::detail
