#include "ndtom_apps/command_line.h"

namespace ndtom::apps {

void forEachArgument(int argc, const char* const argv[], const std::vector<std::string>& flags,
                     const std::function<void(const std::string& name)>& flag,
                     const std::function<void(const std::string& name, const std::string& value)>&
                         option) {
  for (int i = 1; i < argc; ++i) {
    const std::string name = argv[i];
    if (std::find(flags.begin(), flags.end(), name) != flags.end()) {
      flag(name);
      continue;
    }
    if (i + 1 >= argc) throw UsageError(name + ": missing value (see --help)");
    option(name, argv[++i]);
  }
}

UsageError unknownOption(const std::string& name) {
  return UsageError("unknown option '" + name + "' (see --help)");
}

}  // namespace ndtom::apps
