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

std::vector<Argument> splitArguments(
    int argc, const char* const argv[],
    const std::function<std::optional<bool>(const std::string& name)>& takes_value) {
  std::vector<Argument> arguments;
  for (int i = 1; i < argc; ++i) {
    std::string name = argv[i], value;
    const size_t eq = name.find('=');
    const bool inline_value = name.rfind("--", 0) == 0 && eq != std::string::npos;
    if (inline_value) {
      value = name.substr(eq + 1);
      name = name.substr(0, eq);
    }
    if (name.size() < 2 || name[0] != '-') {
      arguments.push_back({"", argv[i]});
      continue;
    }
    const std::optional<bool> needs_value = takes_value(name);
    if (!needs_value) throw UsageError(name + ": unknown option (see --help)");
    if (!*needs_value && inline_value) throw UsageError(name + ": takes no value");
    if (*needs_value && !inline_value) {
      if (i + 1 >= argc) throw UsageError(name + ": missing value");
      value = argv[++i];
    }
    arguments.push_back({name, value});
  }
  return arguments;
}

UsageError unknownOption(const std::string& name) {
  return UsageError("unknown option '" + name + "' (see --help)");
}

}  // namespace ndtom::apps
