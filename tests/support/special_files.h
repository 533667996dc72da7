// Files that are not regular files, for tests of readers that must refuse them: a FIFO (an
// old reader would wait for a writer forever) and /dev/zero (it never ends).
#pragma once

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <chrono>
#include <condition_variable>
#include <mutex>
#include <string>
#include <thread>

namespace ndtom::testing {

/// A FIFO at `path`, held open for reading and writing by this object for at most `seconds`
/// (or until it is destroyed): a reader that opens it anyway sees the end of the file then,
/// instead of blocking the test for ever.
class Fifo {
 public:
  explicit Fifo(const std::string& path, double seconds = 2.0) : path_(path) {
    ::unlink(path.c_str());
    ::mkfifo(path.c_str(), 0600);
    fd_ = ::open(path.c_str(), O_RDWR | O_NONBLOCK);
    closer_ = std::thread([this, seconds] {
      std::unique_lock<std::mutex> lock(mutex_);
      done_.wait_for(lock, std::chrono::duration<double>(seconds), [this] { return finished_; });
      ::close(fd_);
    });
  }
  ~Fifo() {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      finished_ = true;
    }
    done_.notify_one();
    closer_.join();
    ::unlink(path_.c_str());
  }
  Fifo(const Fifo&) = delete;
  Fifo& operator=(const Fifo&) = delete;
  const std::string& path() const { return path_; }

 private:
  std::string path_;
  int fd_ = -1;
  std::mutex mutex_;
  std::condition_variable done_;
  bool finished_ = false;
  std::thread closer_;
};

inline const std::string kEndlessFile = "/dev/zero";

}  // namespace ndtom::testing
