// gzip compression streamed on several threads: the bytes are cut into parts of a few MB,
// each compressed into a gzip member of its own while the next part fills. Concatenated
// members are one valid gzip file (RFC 1952, 2.2) that zlib's gzread, and so MRPT's
// CFileGZInputStream, reads as a whole. Memory: a few parts, never the whole input.
#pragma once

#include <cstddef>
#include <cstdint>
#include <deque>
#include <future>
#include <string>

#include "ndtom/atomic_file.h"

namespace ndtom::mapper {

class GzipMemberWriter {
 public:
  static constexpr size_t kPartBytes = size_t(4) << 20;

  /// Compresses at `level` (1 fastest .. 9 best) into `out`, on up to `threads` threads.
  GzipMemberWriter(const ndtom::FileSink& out, int level, int threads);
  /// Waits for the parts in flight (their output is dropped if finish() was not called).
  ~GzipMemberWriter();
  GzipMemberWriter(const GzipMemberWriter&) = delete;
  GzipMemberWriter& operator=(const GzipMemberWriter&) = delete;

  void write(const void* data, size_t size);
  /// Compresses what is left and writes every member, in order. Throws std::runtime_error if
  /// zlib fails, or what `out` throws.
  void finish();

 private:
  void launchPart();
  void writeOldest();

  const ndtom::FileSink& out_;
  int level_;
  size_t max_in_flight_;
  std::string part_;
  std::deque<std::future<std::string>> in_flight_;
  bool any_part_ = false;
};

}  // namespace ndtom::mapper
