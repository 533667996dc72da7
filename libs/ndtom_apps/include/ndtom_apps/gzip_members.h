// gzip compression streamed on several threads: the bytes are cut into parts of a few MB,
// each compressed into a gzip member of its own (libdeflate, whole-buffer) while the next
// part fills. Concatenated members are one valid gzip file (RFC 1952, 2.2) that zlib's gzread,
// and so MRPT's CFileGZInputStream, reads as a whole. Memory: a few parts, never the whole
// input.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <deque>
#include <future>
#include <memory>
#include <string>

#include "ndtom_internal/atomic_file.h"

namespace ndtom::mapper {

class GzipMemberWriter {
 public:
  static constexpr size_t kPartBytes = size_t(4) << 20;

  /// Compresses at `level` (libdeflate's: 1 fastest .. 12 best) into `out`, on up to
  /// `threads` threads.
  GzipMemberWriter(const ndtom::FileSink& out, int level, int threads);
  /// Waits for the parts in flight (their output is dropped if finish() was not called).
  ~GzipMemberWriter();
  GzipMemberWriter(const GzipMemberWriter&) = delete;
  GzipMemberWriter& operator=(const GzipMemberWriter&) = delete;

  /// Inline for the common case: an MRPT archive writes a scene a float at a time.
  void write(const void* data, size_t size) {
    if (size < kPartBytes - fill_) {
      char* to = part_.get() + fill_;
      fill_ += size;
      // Copies of a constant size are a load and a store; memcpy of any size is a call.
      if (size == 4) return std::memcpy(to, data, 4), void();
      if (size == 1) return std::memcpy(to, data, 1), void();
      if (size == 8) return std::memcpy(to, data, 8), void();
      std::memcpy(to, data, size);
      return;
    }
    writeAcrossParts(data, size);
  }
  /// Compresses what is left and writes every member, in order. Throws std::runtime_error if
  /// the compressor fails, or what `out` throws.
  void finish();

 private:
  void writeAcrossParts(const void* data, size_t size);
  void launchPart();
  void writeOldest();

  const ndtom::FileSink& out_;
  int level_;
  size_t max_in_flight_;
  std::unique_ptr<char[]> part_;  ///< kPartBytes, the first fill_ of them written
  size_t fill_ = 0;
  std::deque<std::future<std::string>> in_flight_;
  bool any_part_ = false;
};

}  // namespace ndtom::mapper
