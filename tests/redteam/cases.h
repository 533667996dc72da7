// The red team's cases: one hostile input each, the program that reads it, what a correct
// program does with it, and how to tell a silently wrong result or lost data afterwards.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <functional>
#include <memory>
#include <set>
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
  /// If set, the command line, made after setup (when it depends on what setup made).
  std::function<std::vector<std::string>()> make_argv;
  /// After the run: "" if fine, else "silent wrong: ...", "data loss: ..." or "mrpt: ..." (a
  /// crash that MRPT's own reader has on the same file).
  std::function<std::string(const Outcome&)> check;
  std::string cwd;
  /// A refusal must be one line on stderr. Off for MRPT's own programs, which print their
  /// exception's trace: there the check judges the message.
  bool one_line = true;
  /// Taken by --sample (ctest's redteam_sample): false for cases of many seconds.
  bool sampled = true;
};

/// Where things are: the programs under test, the data shipped with the project, a scratch
/// folder for the inputs.
struct Context {
  std::string mapper, probe, work, lidar, tum;
  /// Issue #38's programs (empty or missing: their cases are left out), the plugin for MRPT's
  /// programs, and this harness (its --write makes hostile maps in a child process).
  std::string localizer, worldgen, rawlog_from_pcd, mpi_mapper, plugin, self;
  /// Loaded before the plugin into MRPT's programs: the ASan runtime in the sanitizer build
  /// (an instrumented plugin in an uninstrumented program needs it first).
  std::string preload;
  /// A fresh empty folder under `work`.
  std::string folder(const std::string& name) const;
  /// A folder of the lidar's first `scans` PCDs and their poses.txt; returns it.
  std::string lidarFolder(const std::string& name, int scans) const;
  /// ndtom-map INPUT -o OUT -q [--no-pictures] args...
  std::vector<std::string> mapper_args(const std::string& input, const std::string& out,
                                       std::vector<std::string> args, bool pictures = false) const;
  /// ndtom-localize MAP INPUT -o OUT -q --no-pictures args...
  std::vector<std::string> localizer_args(const std::string& map, const std::string& input,
                                          const std::string& out,
                                          std::vector<std::string> args) const;
  /// A small generated city (ndtom-worldgen, 11 scans 10 m apart), made once per seed:
  /// its folder (scan*.pcd, poses.txt, times.txt).
  std::string city(int seed) const;
  /// The map of city(seed) by ndtom-map with `args` (0.2 m cells, rays cut at 40 m), made
  /// once per `name`: its PREFIX (PREFIX.ndtom, PREFIX.ndtommap, ...).
  std::string cityMap(int seed, const std::string& name, std::vector<std::string> args = {}) const;
  /// Runs `ndtom-redteam --write args...` (hostile_maps.h); throws if it fails.
  void writeHostile(const std::vector<std::string>& args) const;
  /// Folders and maps already made (shared by the copies of the context in the cases).
  std::shared_ptr<std::set<std::string>> made = std::make_shared<std::set<std::string>>();
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
// Issue #38's surfaces (cases_localize.cpp, cases_options.cpp, cases_plugin.cpp).
std::vector<Case> localizeCases(const Context& c);  // 8: localization and tiled maps
std::vector<Case> optionCases(const Context& c);    // 9: drawing, generator, spill options
std::vector<Case> pluginCases(const Context& c);    // 10: the plugin's .ini, outputs

/// KITTI poses.txt: the positions (sensor -> world translations), one per line.
std::vector<Eigen::Vector3d> kittiPositions(const std::string& path);
/// The pose on line `line_index` of KITTI `poses`, moved by dx, dy (m) and yaw (degrees), as
/// ndtom-localize's --initial "x y z qx qy qz qw".
std::string initialPose(const std::string& poses, double dx = 0, double dy = 0, double yaw_deg = 0,
                        size_t line_index = 0);
/// ndtom-localize's PREFIX.scans.csv against the scans' true positions: "" if every scan it
/// calls placed (not lost) is within `tolerance` m of its truth (with `none_placed`: if
/// none is placed at all), else "silent wrong: ..." naming the first and counting them.
std::string placedScansCheck(const std::string& prefix, const std::vector<Eigen::Vector3d>& truth,
                             double tolerance, bool none_placed = false);

}  // namespace redteam
