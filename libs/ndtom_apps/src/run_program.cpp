#include "ndtom_apps/run_program.h"

#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <iostream>
#include <new>

#include "ndtom_apps/option_values.h"

namespace ndtom::apps {

namespace {

// Whether what the program printed reached the standard output: a full disk behind a
// redirection fails the run like any other write. `why`: the reason, where the system gave one.
bool standardOutputWritten(std::string& why) {
  errno = 0;
  std::cout.flush();  // std::cout writes through stdout: this flushes both
  const bool written = std::fflush(stdout) == 0 && !std::ferror(stdout) && std::cout.good();
  // A write that failed earlier, when the buffer filled, left only the error flag: no reason.
  if (!written && errno) why = std::string(": ") + std::strerror(errno);
  return written;
}

}  // namespace

int runProgram(const std::string& name, const std::function<int()>& body) {
  try {
    const int status = body();
    std::string why;
    if (standardOutputWritten(why)) return status;
    std::fprintf(stderr, "%s: cannot write the standard output%s\n", name.c_str(), why.c_str());
    return 1;
  } catch (const UsageError& e) {
    std::fprintf(stderr, "%s: %s\n", name.c_str(), e.what());
    return 2;
  } catch (const std::bad_alloc&) {
    // "std::bad_alloc" alone says nothing to a user.
    std::fprintf(stderr,
                 "%s%s: out of memory: the system refused an allocation (std::bad_alloc); the "
                 "machine has less free memory than the work needs\n",
                 isatty(STDERR_FILENO) ? "\n" : "", name.c_str());
    return 1;
  } catch (const std::exception& e) {
    // After a progress line rewritten in place on a terminal, start a fresh line.
    std::fprintf(stderr, "%s%s: %s\n", isatty(STDERR_FILENO) ? "\n" : "", name.c_str(),
                 oneLineMessage(e).c_str());
    return 1;
  }
}

std::string oneLineMessage(const std::exception& e) {
  const std::string what = e.what();
  const std::string marker = "Message:";
  size_t begin = what.find(marker);
  begin = begin == std::string::npos ? 0 : begin + marker.size();
  std::string line = trim(what.substr(begin, what.find('\n', begin) - begin));
  return line.empty() ? trim(what) : line;
}

}  // namespace ndtom::apps
