#include "ndtom_internal/atomic_file.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <stdexcept>

namespace ndtom {
namespace {

[[noreturn]] void failWith(const std::string& what, const std::string& path, int err) {
  throw std::runtime_error(what + " " + path + ": " + std::strerror(err));
}

// Writes `path` through `fill` and syncs it; on failure removes it and throws naming `name`.
void writeSynced(const std::string& path, const std::string& name, const FileFiller& fill) {
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) failWith("cannot write", name, errno);
  int err = 0;
  const FileSink sink = [&](const void* data, size_t size) {
    const auto* bytes = static_cast<const char*>(data);
    for (size_t done = 0; done < size;) {
      const ssize_t n = ::write(fd, bytes + done, size - done);
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) {
        err = n < 0 ? errno : EIO;
        failWith("cannot write", name, err);
      }
      done += size_t(n);
    }
  };
  try {
    fill(sink);
  } catch (...) {
    ::close(fd);
    ::unlink(path.c_str());
    throw;
  }
  if (::fsync(fd) != 0) err = errno;
  if (::close(fd) != 0 && err == 0) err = errno;
  if (err != 0) {
    ::unlink(path.c_str());
    failWith("cannot write", name, err);
  }
}

}  // namespace

std::string temporaryPathFor(const std::string& path) {
  return path + kTemporaryMarker + std::to_string(::getpid());
}

void renameFile(const std::string& from, const std::string& to) {
  if (std::rename(from.c_str(), to.c_str()) != 0) failWith("cannot rename to", to, errno);
}

void writeFileAtomically(const std::string& path, const void* data, size_t size) {
  writeFileAtomically(path, [&](const FileSink& write) { write(data, size); });
}

void writeFileAtomically(const std::string& path, const FileFiller& fill) {
  const std::string tmp = temporaryPathFor(path);
  writeSynced(tmp, path, fill);
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    const int err = errno;
    ::unlink(tmp.c_str());
    failWith("cannot rename to", path, err);
  }
}

void writeFileSynced(const std::string& path, const FileFiller& fill) {
  writeSynced(path, path, fill);
}

void syncFile(const std::string& path) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) failWith("cannot write", path, errno);
  const int err = ::fsync(fd) == 0 ? 0 : errno;
  ::close(fd);
  if (err != 0) failWith("cannot write", path, err);
}

}  // namespace ndtom
