// Reading files whose kind and size are not trusted. Only regular files are read: a FIFO
// would block the reader forever and /dev/zero never ends. And each kind of file has a size
// limit, checked before a byte is read.
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>

namespace ndtom {

/// A file that cannot be read as input: missing, unreadable, not a regular file, too large.
/// The message names the file.
class InputFileError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// The size of `path` if it is a regular file of at most `max_bytes`; else throws
/// InputFileError "<what> <path>: <why>" (e.g. "pose file /tmp/p: a FIFO, not a regular file").
/// Never opens the file, so a FIFO does not block.
uint64_t checkInputFile(const std::string& path, uint64_t max_bytes, const std::string& what);

/// The whole content of a regular file of at most `max_bytes`, checked as above (and again on
/// the opened file, so one swapped for a FIFO in between is refused too).
std::string readInputFile(const std::string& path, uint64_t max_bytes, const std::string& what);

/// "12.3 MB" (10^6 bytes), for messages about sizes.
std::string megabytes(uint64_t bytes);

}  // namespace ndtom
