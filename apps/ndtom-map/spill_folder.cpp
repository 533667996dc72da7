#include "spill_folder.h"

#include <signal.h>
#include <unistd.h>

#include <cerrno>
#include <filesystem>

#include "ndtom_apps/option_values.h"

namespace ndtom::mapper {
namespace {

namespace fs = std::filesystem;
const std::string kTag = ".spill-";

// A spill folder of this prefix whose run is over: "map.spill-123" with no process 123.
bool leftByDeadRun(const std::string& name, const std::string& stem) {
  if (name.rfind(stem + kTag, 0) != 0) return false;
  const std::string digits = name.substr(stem.size() + kTag.size());
  if (digits.empty() || digits.size() > 9 ||
      digits.find_first_not_of("0123456789") != std::string::npos)
    return false;
  return ::kill(pid_t(std::stol(digits)), 0) != 0 && errno == ESRCH;
}

}  // namespace

SpillFolder::SpillFolder(const std::string& prefix, const std::string& dir) {
  const fs::path base(prefix);
  const fs::path parent = !dir.empty()                 ? fs::path(dir)
                          : base.parent_path().empty() ? fs::path(".")
                                                       : base.parent_path();
  // Checked before the work starts: the folder (created if missing), then a new folder in it.
  const std::string option = dir.empty() ? "-o " + prefix : "--spill-dir " + dir;
  const auto refuse = [&](const std::string& why) {
    throw apps::UsageError(option + ": not a writable folder (" + why + ")");
  };
  std::error_code ec;
  if (!fs::exists(parent, ec)) {
    fs::create_directories(parent, ec);
    if (ec) refuse("cannot create it: " + ec.message());
  }
  if (!fs::is_directory(parent, ec)) refuse("a file");
  const std::string stem = base.filename().string();
  for (const auto& entry : fs::directory_iterator(parent, ec))
    if (leftByDeadRun(entry.path().filename().string(), stem)) fs::remove_all(entry.path(), ec);
  path_ = (parent / (stem + kTag + std::to_string(::getpid()))).string();
  fs::remove_all(path_, ec);  // a killed run's with the same pid
  if (!fs::create_directory(path_, ec))
    refuse("cannot create the spill folder " + path_ +
           " in it: " + (ec ? ec.message() : std::string("it exists")));
}

SpillFolder::~SpillFolder() {
  std::error_code ec;
  fs::remove_all(path_, ec);
}

}  // namespace ndtom::mapper
