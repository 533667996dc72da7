#include "ndtom_internal/input_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>

namespace ndtom {
namespace {

[[noreturn]] void fail(const std::string& what, const std::string& path, const std::string& why) {
  throw InputFileError(what + " " + path + ": " + why);
}

// Why a file of this status cannot be read as input, or "" if it can.
std::string refusal(const struct stat& st, uint64_t max_bytes) {
  if (S_ISDIR(st.st_mode)) return "a folder, not a file";
  if (S_ISFIFO(st.st_mode)) return "a FIFO, not a regular file";
  if (S_ISCHR(st.st_mode) || S_ISBLK(st.st_mode)) return "a device, not a regular file";
  if (!S_ISREG(st.st_mode)) return "not a regular file";
  if (uint64_t(st.st_size) > max_bytes)
    return megabytes(uint64_t(st.st_size)) + ", more than the " + megabytes(max_bytes) +
           " such a file may have";
  return "";
}

}  // namespace

std::string megabytes(uint64_t bytes) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.1f MB", double(bytes) / 1e6);
  return text;
}

uint64_t checkInputFile(const std::string& path, uint64_t max_bytes, const std::string& what) {
  struct stat st;
  if (::stat(path.c_str(), &st) != 0) fail(what, path, std::strerror(errno));
  const std::string why = refusal(st, max_bytes);
  if (!why.empty()) fail(what, path, why);
  return uint64_t(st.st_size);
}

std::string readInputFile(const std::string& path, uint64_t max_bytes, const std::string& what) {
  checkInputFile(path, max_bytes, what);
  // O_NONBLOCK: should the path have become a FIFO since the check, open() must not wait.
  const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) fail(what, path, std::strerror(errno));
  std::string bytes;
  std::string why;
  struct stat st;
  if (::fstat(fd, &st) != 0) {
    why = std::strerror(errno);
  } else if (why = refusal(st, max_bytes); why.empty()) {
    // One byte more than the size: reading it means the file changed since fstat().
    bytes.resize(size_t(st.st_size) + 1);
    size_t done = 0;
    while (done < bytes.size()) {
      const ssize_t n = ::read(fd, &bytes[done], bytes.size() - done);
      if (n < 0 && errno == EINTR) continue;
      if (n < 0) {
        why = std::strerror(errno);
        break;
      }
      if (n == 0) break;
      done += size_t(n);
    }
    if (why.empty() && done != size_t(st.st_size)) why = "changed while it was read";
    bytes.resize(done);
  }
  ::close(fd);
  if (!why.empty()) fail(what, path, why);
  return bytes;
}

}  // namespace ndtom
