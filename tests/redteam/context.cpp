#include <filesystem>
#include <fstream>
#include <stdexcept>

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

std::vector<std::string> Context::localizer_args(const std::string& map, const std::string& input,
                                                 const std::string& out,
                                                 std::vector<std::string> args) const {
  std::vector<std::string> argv = {localizer, map, input, "-o", out, "-q", "--no-pictures"};
  argv.insert(argv.end(), args.begin(), args.end());
  return argv;
}

namespace {

// Runs a program the cases need as their input; throws (a harness error) if it fails.
void mustRun(const std::vector<std::string>& argv, const std::string& what) {
  RunLimits limits;
  limits.timeout_s = 300;
  const Outcome o = runCommand(argv, limits);
  if (o.exit_code != 0)
    throw std::runtime_error(what + " failed (exit " + std::to_string(o.exit_code) + ", signal " +
                             std::to_string(o.signal) + "): " + o.err.substr(0, 300));
}

}  // namespace

std::string Context::city(int seed) const {
  const std::string dir = work + "/cities/seed" + std::to_string(seed);
  if (made->insert(dir).second) {
    fs::remove_all(dir);
    // 0.1 km in 10 m steps: 11 scans of the default lidar (32 rings x 900 rays) cut at 40 m,
    // a city of 2 x 2 blocks. From the first true pose ndtom-localize places every scan
    // within millimetres (a few seconds in all).
    mustRun({worldgen, dir, "--km", "0.1", "--step", "10", "--max-range", "40", "--seed",
             std::to_string(seed), "--threads", "2", "-q"},
            "ndtom-worldgen (the city of seed " + std::to_string(seed) + ")");
  }
  return dir;
}

std::string Context::cityMap(int seed, const std::string& name,
                             std::vector<std::string> args) const {
  const std::string prefix = work + "/cities/map-" + name;
  if (made->insert(prefix).second) {
    std::vector<std::string> all = {"--max-range", "40"};
    all.insert(all.end(), args.begin(), args.end());
    mustRun(mapper_args(city(seed), prefix, all), "ndtom-map (the city map " + name + ")");
  }
  return prefix;
}

void Context::writeHostile(const std::vector<std::string>& args) const {
  std::vector<std::string> argv = {self, "--write"};
  argv.insert(argv.end(), args.begin(), args.end());
  mustRun(argv, "ndtom-redteam --write " + args.front());
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
