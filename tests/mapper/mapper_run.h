// Running ndtom-map from a test: a fresh output folder per test, the exit code, stdout and
// stderr, and the few values a test reads back from the JSON summary.
#pragma once

#include <cstdlib>

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace mapper_test {

namespace fs = std::filesystem;

const std::string kMapper = NDTOM_MAP_EXE;
const std::string kTum = std::string(NDTOM_SOURCE_DIR) + "/share/data/tum-fr2-pioneer-slam2";
const std::string kLidar = std::string(NDTOM_TEST_DATA_DIR) + "/balm-realworld";
const std::string kSenaRawlog =
    std::string(MRPT_DATASETS) + "/2006-01ENE-21-SENA_Telecom Faculty_one_loop_only.rawlog";

struct ProgramRun {
  int exit_code = -1;
  std::string out, err;
};

inline std::string readText(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

/// An empty folder for one test's files, removed afterwards.
class TempDir {
 public:
  TempDir() {
    const auto* test = ::testing::UnitTest::GetInstance()->current_test_info();
    path_ = fs::temp_directory_path() / ("ndtom-map-" + std::string(test->test_suite_name()) + "-" +
                                         test->name() + "-" + std::to_string(getpid()));
    fs::remove_all(path_);
    fs::create_directories(path_);
  }
  ~TempDir() {
    if (!std::getenv("NDTOM_KEEP_TEST_FILES")) fs::remove_all(path_);  // kept to debug a test
  }
  const fs::path& path() const { return path_; }
  fs::path operator/(const std::string& name) const { return path_ / name; }

 private:
  fs::path path_;
};

inline std::string quoted(const std::string& s) {
  return "'" + s + "'";
}

/// Runs `program ARGS` (arguments already quoted as needed) with output files in `dir`.
inline ProgramRun runExecutable(const std::string& program, const std::string& args,
                                const TempDir& dir) {
  const fs::path out = dir / "stdout.txt", err = dir / "stderr.txt";
  const std::string command = quoted(program) + " " + args + " >" + quoted(out.string()) + " 2>" +
                              quoted(err.string()) + " </dev/null";
  const int status = std::system(command.c_str());
  ProgramRun run{WIFEXITED(status) ? WEXITSTATUS(status) : -1, readText(out), readText(err)};
  fs::remove(out);
  fs::remove(err);
  return run;
}

/// Runs `ndtom-map ARGS`.
inline ProgramRun runMapper(const std::string& args, const TempDir& dir) {
  return runExecutable(kMapper, args, dir);
}

/// The number after the first `"key":` in `json` at or after `anchor`; NaN if absent.
inline double jsonNumber(const std::string& json, const std::string& key,
                         const std::string& anchor = "") {
  const size_t from = anchor.empty() ? 0 : json.find("\"" + anchor + "\"");
  if (from == std::string::npos) return std::nan("");
  const size_t at = json.find("\"" + key + "\":", from);
  if (at == std::string::npos) return std::nan("");
  return std::strtod(json.c_str() + at + key.size() + 3, nullptr);
}

/// Equal byte strings, or where they first differ (never the bytes themselves: maps are big).
inline ::testing::AssertionResult sameBytes(const std::string& a, const std::string& b) {
  if (a == b) return ::testing::AssertionSuccess();
  size_t i = 0;
  while (i < a.size() && i < b.size() && a[i] == b[i]) ++i;
  return ::testing::AssertionFailure()
         << "sizes " << a.size() << " and " << b.size() << ", first difference at byte " << i;
}

/// Files in `dir` whose name starts with `stem` and a dot (the outputs of PREFIX dir/stem).
inline std::vector<std::string> outputsOf(const TempDir& dir, const std::string& stem) {
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(dir.path())) {
    const std::string name = e.path().filename().string();
    if (name.rfind(stem + ".", 0) == 0) names.push_back(name);
  }
  return names;
}

}  // namespace mapper_test
