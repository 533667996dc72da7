#include "ndtom_apps/run_program.h"

#include <unistd.h>

#include <cstdio>
#include <new>

#include "ndtom_apps/option_values.h"

namespace ndtom::apps {

int runProgram(const std::string& name, const std::function<int()>& body) {
  try {
    return body();
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
