// The red team's cases: one hostile input each, the program that reads it, what a correct
// program does with it, and how to tell a silently wrong result or lost data afterwards.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "run_case.h"

namespace redteam {

/// What a correct program does with the input.
enum class Expect { Refuse, Accept, Either };

struct Case {
  std::string category, name;
  std::vector<std::string> argv;
  Expect expect = Expect::Refuse;
  RunLimits limits;
  /// Makes the input files (just before the run, to keep the disk small); returns their size.
  std::function<uint64_t()> setup;
  /// After the run: "" if fine, else "silent wrong: ...", "data loss: ..." or "mrpt: ..." (a
  /// crash that MRPT's own reader has on the same file).
  std::function<std::string(const Outcome&)> check;
  std::string cwd;
};

/// Where things are: the programs under test, the data shipped with the project, a scratch
/// folder for the inputs.
struct Context {
  std::string mapper, probe, work, lidar, tum;
  /// A fresh empty folder under `work`.
  std::string folder(const std::string& name) const;
  /// A folder of the lidar's first `scans` PCDs and their poses.txt; returns it.
  std::string lidarFolder(const std::string& name, int scans) const;
  /// ndtom-map INPUT -o OUT -q [--no-pictures] args...
  std::vector<std::string> mapper_args(const std::string& input, const std::string& out,
                                       std::vector<std::string> args, bool pictures = false) const;
};

/// The cases of one category, with their inputs in one folder of the scratch space.
struct CaseSet {
  CaseSet(const Context& context, const std::string& category, const std::string& folder);
  /// A new case of the category (the reference is valid until the next add).
  Case& add();
  /// A fresh path in the folder, ending in `suffix`.
  std::string path(const std::string& suffix);

  const Context& c;
  std::string category, dir;
  std::vector<Case> cases;
  int id = 0;
};

/// Bytes of the files under `path` (a file or a folder).
uint64_t sizeOf(const std::string& path);

// One function per category of issue #17 (cases_*.cpp).
std::vector<Case> pcdHeaderCases(const Context& c);       // 1: PCD size arithmetic
std::vector<Case> geometryMemoryCases(const Context& c);  // 2: work and memory vs geometry
std::vector<Case> loaderCountCases(const Context& c);     // 3: loader allocations
std::vector<Case> writableCases(const Context& c);        // 4: writable means loadable
std::vector<Case> silentValueCases(const Context& c);     // 5: silent wrong values
std::vector<Case> outputCases(const Context& c);          // 6: all-or-nothing outputs
std::vector<Case> smallCases(const Context& c);           // 7: small ones
std::vector<Case> rawlogCases(const Context& c);          // 7: corrupt MRPT rawlogs

}  // namespace redteam
