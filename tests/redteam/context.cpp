#include <filesystem>
#include <fstream>

#include "cases.h"

namespace fs = std::filesystem;

namespace redteam {

std::string Context::folder(const std::string& name) const {
  const fs::path dir = fs::path(work) / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir.string();
}

std::string Context::lidarFolder(const std::string& name, int scans) const {
  const std::string dir = folder(name);
  std::ifstream in(lidar + "/poses.txt");
  std::ofstream poses(dir + "/poses.txt");
  std::string line;
  for (int i = 0; i < scans && std::getline(in, line); ++i) {
    poses << line << "\n";
    const std::string pcd = "full" + std::to_string(i) + ".pcd";
    fs::copy_file(lidar + "/" + pcd, dir + "/" + pcd);
  }
  return dir;
}

std::vector<std::string> Context::mapper_args(const std::string& input, const std::string& out,
                                              std::vector<std::string> args, bool pictures) const {
  std::vector<std::string> argv = {mapper, input, "-o", out, "-q"};
  if (!pictures) argv.push_back("--no-pictures");
  argv.insert(argv.end(), args.begin(), args.end());
  return argv;
}

CaseSet::CaseSet(const Context& context, const std::string& category_name,
                 const std::string& folder)
    : c(context), category(category_name), dir(context.folder(folder)) {}

Case& CaseSet::add() {
  cases.emplace_back();
  cases.back().category = category;
  return cases.back();
}

std::string CaseSet::path(const std::string& suffix) {
  return dir + "/f" + std::to_string(id++) + suffix;
}

uint64_t sizeOf(const std::string& path) {
  std::error_code ec;
  if (fs::is_regular_file(path, ec)) return fs::file_size(path, ec);
  uint64_t bytes = 0;
  for (const auto& e : fs::recursive_directory_iterator(path, ec))
    if (e.is_regular_file(ec)) bytes += e.file_size(ec);
  return bytes;
}

}  // namespace redteam
