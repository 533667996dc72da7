// Class 6 of issue #17: a rerun that cannot replace its outputs, or is interrupted, must leave
// the previous set whole and no temporaries; a write that fails must say which file.
#include <signal.h>

#include <filesystem>
#include <fstream>
#include <map>

#include "cases.h"
#include "hostile_files.h"

namespace fs = std::filesystem;

namespace redteam {
namespace {

// The outputs under `prefix` and a hash of their bytes (not the bytes: the harness would grow
// with every set it keeps).
std::map<std::string, size_t> outputSet(const std::string& prefix) {
  std::map<std::string, size_t> set;
  const fs::path base(prefix);
  for (const auto& e : fs::directory_iterator(base.parent_path())) {
    const std::string name = e.path().filename().string();
    if (name.rfind(base.filename().string() + ".", 0) == 0 && e.is_regular_file())
      set[name] = std::hash<std::string>{}(readFile(e.path().string()));
  }
  return set;
}

// "" if the outputs now are all those of `before`, or (if `new_allowed`) all new ones, with
// no temporary left; else what is wrong.
std::string wholeSet(const std::map<std::string, size_t>& before,
                     const std::map<std::string, size_t>& after, bool new_allowed) {
  for (const auto& [name, bytes] : after)
    if (name.find(".ndtom-tmp-") != std::string::npos || name.find(".ndtom-old-") != std::string::npos)
      return "data loss: " + name + " left behind";
  size_t same = 0, changed = 0;
  for (const auto& [name, bytes] : before) {
    const auto it = after.find(name);
    if (it == after.end()) return "data loss: " + name + " gone";
    ++(it->second == bytes ? same : changed);
  }
  if (changed == 0 || (new_allowed && same == 0)) return "";
  return "data loss: " + std::to_string(changed) + " outputs new, " + std::to_string(same) + " old";
}

// A run that ended by our signal may have committed (all new) or not (all old).
bool mayHaveCommitted(const Outcome& o) {
  return o.exit_code == 0 || o.signalled_by_us;
}

}  // namespace

std::vector<Case> outputCases(const Context& c) {
  CaseSet set(c, "6 all-or-nothing outputs", "outputs");
  int& id = set.id;
  const std::vector<std::string> suffixes = {".ndtom",   ".ndtommap", ".3Dscene",
                                             ".top.png", ".3d.png",   ".summary.json"};
  // One output made a folder, then a rerun with other options.
  for (const std::string& blocked : suffixes) {
    Case& k = set.add();
    k.name = "rerun with " + blocked + " replaced by a folder";
    const std::string out = c.work + "/blocked" + std::to_string(id++) + "/out";
    k.argv = c.mapper_args(c.tum, out, {"--max-scans", "4"}, true);
    auto before = std::make_shared<std::map<std::string, size_t>>();
    k.setup = [&c, out, blocked, before] {
      runCommand(c.mapper_args(c.tum, out, {"--max-scans", "2"}, true));
      *before = outputSet(out);
      before->erase(fs::path(out + blocked).filename().string());
      fs::remove(out + blocked);
      fs::create_directories(out + blocked);
      return uint64_t(1400000);  // the TUM frames
    };
    k.check = [out, before](const Outcome&) { return wholeSet(*before, outputSet(out), false); };
  }
  // SIGTERM and SIGINT at points of a run that writes large outputs.
  for (const int signal : {SIGTERM, SIGINT})
    for (const double after : {0.3, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 8.0}) {
      Case& k = set.add();
      k.name = std::string(signal == SIGTERM ? "SIGTERM" : "SIGINT") + " after " +
               std::to_string(after).substr(0, 3) + " s";
      k.expect = Expect::Either;
      const std::string out = c.work + "/signal" + std::to_string(id++) + "/out";
      const std::string lidar = c.lidar;
      k.argv = c.mapper_args(lidar, out, {"--resolution", "0.1"}, true);
      k.limits.signal = signal;
      k.limits.signal_after_s = after;
      auto before = std::make_shared<std::map<std::string, size_t>>();
      k.setup = [&c, out, before, lidar] {
        runCommand(c.mapper_args(lidar, out, {"--resolution", "0.4"}, true));
        *before = outputSet(out);
        return sizeOf(lidar);
      };
      k.check = [out, before](const Outcome& o) {
        return wholeSet(*before, outputSet(out), mayHaveCommitted(o));
      };
    }
  // SIGKILL cannot be caught: the next run must clean up after it.
  for (const double after : {1.5, 3.0, 5.0}) {
    Case& k = set.add();
    k.name = "rerun after SIGKILL at " + std::to_string(after).substr(0, 3) + " s";
    k.expect = Expect::Accept;
    const std::string out = c.work + "/killed" + std::to_string(id++) + "/out";
    k.argv = c.mapper_args(c.tum, out, {"--max-scans", "2"});
    k.setup = [&c, out, after] {
      RunLimits kill;
      kill.signal = SIGKILL;
      kill.signal_after_s = after;
      runCommand(c.mapper_args(c.lidar, out, {"--resolution", "0.1"}, true), kill);
      return uint64_t(1400000);
    };
    k.check = [out](const Outcome& o) {
      return o.exit_code == 0 ? wholeSet({}, outputSet(out), true) : "";
    };
  }
  // The user's files beside the outputs, named like leftovers of a dead run: not ours.
  {
    Case& k = set.add();
    k.name = "user's files named like leftovers";
    k.expect = Expect::Accept;
    const std::string out = c.work + "/lookalike" + std::to_string(id++) + "/run";
    k.argv = c.mapper_args(c.tum, out, {"--max-scans", "2"});
    const std::vector<std::string> names = {".ndtom.old-20241203", ".3Dscene.old-424242",
                                            ".summary.json.tmp-777777", ".mydata.old-31337"};
    k.setup = [out, names] {
      fs::create_directories(fs::path(out).parent_path());
      for (const std::string& n : names) std::ofstream(out + n) << "mine";
      return uint64_t(1400000);
    };
    k.check = [out, names](const Outcome&) -> std::string {
      for (const std::string& n : names)
        if (!fs::exists(out + n)) return "data loss: the user's " + out + n + " is gone";
      return "";
    };
  }
  // Writes that fail (a file-size limit, as a full disk): the message names the file.
  for (const uint64_t limit : {uint64_t(1), uint64_t(1000), uint64_t(50000), uint64_t(200000),
                               uint64_t(400000), uint64_t(1000000), uint64_t(3000000)}) {
    Case& k = set.add();
    k.name = "files limited to " + std::to_string(limit) + " bytes";
    k.expect = Expect::Either;  // large enough, the run succeeds
    const std::string out = c.work + "/full" + std::to_string(id++) + "/out";
    k.argv = c.mapper_args(c.tum, out, {"--max-scans", "3"}, true);
    k.limits.file_size = limit;
    auto before = std::make_shared<std::map<std::string, size_t>>();
    k.setup = [&c, out, before] {
      runCommand(c.mapper_args(c.tum, out, {"--max-scans", "1"}, true));
      *before = outputSet(out);
      return uint64_t(1400000);
    };
    k.check = [out, before](const Outcome& o) -> std::string {
      if (o.exit_code == 1 && o.err.find(fs::path(out).parent_path().string()) == std::string::npos)
        return "unclear: the message names no file";
      return wholeSet(*before, outputSet(out), mayHaveCommitted(o));
    };
  }
  return set.cases;
}

}  // namespace redteam
