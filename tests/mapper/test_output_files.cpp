// ndtom-map's outputs are committed all together or not at all (issue #17, class 6): a
// previous set survives a commit that cannot complete, a fatal signal removes the
// temporaries, and the next run removes those of a run that was killed outright.
#include <signal.h>
#include <sys/wait.h>

#include "mapper_run.h"
#include "ndtom_apps/output_files.h"

using namespace ndtom::apps;
namespace fs = std::filesystem;
using mapper_test::readText;
using mapper_test::TempDir;

namespace {

const std::vector<std::string> kSuffixes = {".ndtom", ".ndtommap", ".3Dscene", ".top.png",
                                            ".summary.json"};

// A set of outputs PREFIX + suffix, each holding `tag` and its suffix.
void writeSet(const std::string& prefix, const std::string& tag) {
  OutputFiles out(prefix);
  for (const auto& s : kSuffixes) out.writeBytes("role", s, tag + s);
  out.commit();
}

// The names in `dir` with a temporary or moved-aside tag.
std::vector<std::string> leftovers(const TempDir& dir) {
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(dir.path())) {
    const std::string name = e.path().filename().string();
    if (name.find(".ndtom-tmp-") != std::string::npos || name.find(".ndtom-old-") != std::string::npos)
      names.push_back(name);
  }
  return names;
}

// A process id that has exited: a child that ends at once, waited for.
pid_t deadPid() {
  const pid_t pid = fork();
  if (pid == 0) _exit(0);
  waitpid(pid, nullptr, 0);
  return pid;
}

}  // namespace

TEST(OutputFiles, CommitIsAllOrNothing) {
  TempDir dir;
  const std::string prefix = (dir / "out").string();
  writeSet(prefix, "old");
  // The third output cannot be moved aside (its aside name is taken by a folder that is not
  // empty), after two were already replaced: those two are put back.
  fs::create_directories(prefix + ".3Dscene.ndtom-old-" + std::to_string(getpid()) + "/x");
  {
    OutputFiles out(prefix);
    for (const auto& s : kSuffixes) out.writeBytes("role", s, "new" + s);
    try {
      out.commit();
      FAIL() << "committed";
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find("cannot replace " + prefix + ".3Dscene"),
                std::string::npos)
          << e.what();
    }
  }
  for (const auto& s : kSuffixes) EXPECT_EQ(readText(prefix + s), "old" + s) << s;
  fs::remove_all(prefix + ".3Dscene.ndtom-old-" + std::to_string(getpid()));
  EXPECT_TRUE(leftovers(dir).empty()) << leftovers(dir).front();

  // An output replaced by a folder: refused before anything moves.
  fs::remove(prefix + ".top.png");
  fs::create_directories(prefix + ".top.png");
  {
    OutputFiles out(prefix);
    for (const auto& s : kSuffixes) out.writeBytes("role", s, "new" + s);
    EXPECT_THROW(out.commit(), std::runtime_error);
  }
  for (const auto& s : kSuffixes) {
    if (s == ".top.png") continue;
    EXPECT_EQ(readText(prefix + s), "old" + s) << s;
  }
  EXPECT_TRUE(leftovers(dir).empty());

  // And a commit that can complete replaces them all.
  fs::remove(prefix + ".top.png");
  writeSet(prefix, "new");
  for (const auto& s : kSuffixes) EXPECT_EQ(readText(prefix + s), "new" + s) << s;
  EXPECT_TRUE(leftovers(dir).empty());
}

// Before, SIGTERM while the outputs were written left their temporaries for good.
TEST(OutputFiles, FatalSignalRemovesTheTemporaries) {
  TempDir dir;
  const std::string prefix = (dir / "out").string();
  writeSet(prefix, "old");
  for (const int signal : {SIGTERM, SIGINT, SIGHUP}) {
    const pid_t pid = fork();
    if (pid == 0) {
      OutputFiles out(prefix);
      out.writeBytes("role", ".ndtom", "new");
      out.stage("role", ".top.png");  // staged, being written
      std::ofstream(out.stage("role", ".3Dscene")) << "half";
      raise(signal);
      _exit(0);
    }
    int status = 0;
    waitpid(pid, &status, 0);
    ASSERT_TRUE(WIFSIGNALED(status)) << "the child ended without the signal";
    EXPECT_EQ(WTERMSIG(status), signal);
    EXPECT_TRUE(leftovers(dir).empty()) << leftovers(dir).front();
    for (const auto& s : kSuffixes) EXPECT_EQ(readText(prefix + s), "old" + s) << s;
  }
}

// SIGKILL cannot be caught: the next run with the prefix removes the temporaries of the dead
// run, and puts back an output its commit had moved aside; a live process's are left alone.
TEST(OutputFiles, NextRunCleansUpAfterAKilledOne) {
  TempDir dir;
  const std::string prefix = (dir / "out").string();
  const std::string dead = std::to_string(deadPid());
  const std::string live = std::to_string(getppid());
  std::ofstream(prefix + ".ndtom.ndtom-tmp-" + dead) << "half";
  std::ofstream(prefix + ".coarse2.ndtom.ndtom-tmp-" + dead) << "half";
  std::ofstream(prefix + ".top.png.ndtom-old-" + dead) << "previous";  // out.top.png missing
  std::ofstream(prefix + ".ndtom.ndtom-old-" + dead) << "previous";    // out.ndtom present
  std::ofstream(prefix + ".ndtom") << "committed";
  std::ofstream(prefix + ".3Dscene.ndtom-tmp-" + live) << "someone else's";
  std::ofstream(dir / ("other.ndtom.ndtom-tmp-" + dead)) << "another prefix";
  { OutputFiles out(prefix); }
  std::vector<std::string> left = leftovers(dir);
  std::sort(left.begin(), left.end());
  EXPECT_EQ(left, (std::vector<std::string>{"other.ndtom.ndtom-tmp-" + dead,
                                            "out.3Dscene.ndtom-tmp-" + live}));
  EXPECT_EQ(readText(prefix + ".top.png"), "previous");
  EXPECT_EQ(readText(prefix + ".ndtom"), "committed");
}

// The user's own files that look like leftovers ("keep/run.ndtom.old-20241203") are not this
// program's: a run leaves them as they are, whatever number ends their name.
TEST(OutputFiles, UsersFilesThatLookLikeLeftoversAreLeftAlone) {
  TempDir dir;
  const std::string prefix = (dir / "run").string();
  const std::string dead = std::to_string(deadPid());
  const std::vector<std::string> users = {".ndtom.old-20241203", ".3Dscene.old-424242",
                                          ".summary.json.tmp-777777", ".mydata.old-31337",
                                          ".ndtom.tmp-" + dead, ".top.png.old-" + dead};
  for (const std::string& s : users) std::ofstream(prefix + s) << "mine" << s;
  {
    OutputFiles out(prefix);
    out.writeBytes("map", ".ndtom", "new");
    out.writeBytes("summary", ".summary.json", "{}");
    out.commit();
  }
  for (const std::string& s : users) EXPECT_EQ(readText(prefix + s), "mine" + s) << s;
  EXPECT_FALSE(fs::exists(prefix + ".mydata"));
  EXPECT_EQ(readText(prefix + ".ndtom"), "new");
}
