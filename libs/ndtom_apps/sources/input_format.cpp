#include "ndtom_apps/input_format.h"

#include <filesystem>

#include "ndtom_internal/input_file.h"
#include "ndtom_apps/option_values.h"

namespace fs = std::filesystem;

namespace ndtom::apps {
namespace {

using apps::UsageError;

bool endsWith(const std::string& text, const std::string& suffix) {
  return text.size() >= suffix.size() &&
         text.compare(text.size() - suffix.size(), suffix.size(), suffix) == 0;
}

bool hasPcdFiles(const fs::path& folder) {
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(folder, ec))
    if (entry.path().extension() == ".pcd") return true;
  return false;
}

}  // namespace

void requireRegularFile(const std::string& what, const std::string& path) {
  try {
    ndtom::checkInputFile(path, UINT64_MAX, what);
  } catch (const ndtom::InputFileError& e) {
    throw UsageError(e.what());
  }
}

InputFormat inputFormatFromName(const std::string& name) {
  if (name == "auto") return InputFormat::Auto;
  if (name == "rawlog") return InputFormat::Rawlog;
  if (name == "simplemap") return InputFormat::Simplemap;
  if (name == "tum") return InputFormat::TumRgbd;
  if (name == "pcd") return InputFormat::PcdFolder;
  throw UsageError("--format: unknown format '" + name + "' (rawlog, simplemap, tum or pcd)");
}

const char* inputFormatName(InputFormat format) {
  switch (format) {
    case InputFormat::Auto:
      return "auto";
    case InputFormat::Rawlog:
      return "rawlog";
    case InputFormat::Simplemap:
      return "simplemap";
    case InputFormat::TumRgbd:
      return "tum";
    case InputFormat::PcdFolder:
      return "pcd";
  }
  return "unknown";
}

ndtom::io::PoseFormat poseFormatFromName(const std::string& option, const std::string& name) {
  if (name == "auto") return ndtom::io::PoseFormat::Auto;
  if (name == "kitti") return ndtom::io::PoseFormat::Kitti;
  if (name == "tum") return ndtom::io::PoseFormat::Tum;
  throw UsageError(option + ": expected auto, kitti or tum, got '" + name + "'");
}

InputFormat detectInputFormat(const std::string& path) {
  std::error_code ec;
  const fs::file_status status = fs::status(path, ec);
  if (!fs::exists(status)) throw UsageError(path + ": no such file or folder");
  if (fs::is_directory(status)) {
    const fs::path folder(path);
    for (const char* marker : {"associations.txt", "depth.txt", "groundtruth.txt"})
      if (fs::exists(folder / marker)) return InputFormat::TumRgbd;
    if (hasPcdFiles(folder)) return InputFormat::PcdFolder;
    throw UsageError(path +
                     ": folder holds neither a TUM RGB-D sequence (associations.txt, depth.txt) "
                     "nor .pcd files");
  }
  requireRegularFile("INPUT", path);
  if (endsWith(path, ".rawlog") || endsWith(path, ".rawlog.gz")) return InputFormat::Rawlog;
  if (endsWith(path, ".simplemap") || endsWith(path, ".simplemap.gz"))
    return InputFormat::Simplemap;
  throw UsageError(path + ": unknown input format (expected .rawlog, .simplemap[.gz], a TUM " +
                   "RGB-D folder or a folder of .pcd files; or give --format)");
}

}  // namespace ndtom::apps
