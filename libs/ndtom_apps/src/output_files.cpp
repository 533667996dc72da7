#include "ndtom_apps/output_files.h"

#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <stdexcept>

#include "ndtom_apps/json_writer.h"
#include "ndtom_apps/option_values.h"

namespace fs = std::filesystem;

namespace ndtom::apps {
namespace {

// --- Temporaries removed on a fatal signal ----------------------------------------------
// The handler reads this list, so it only changes while those signals are blocked.

constexpr int kFatalSignals[] = {SIGINT, SIGTERM, SIGHUP};
std::vector<std::string> g_temporaries;
struct sigaction g_previous[3];
int g_users = 0;

class SignalsBlocked {
 public:
  SignalsBlocked() {
    sigset_t set;
    sigemptyset(&set);
    for (const int s : kFatalSignals) sigaddset(&set, s);
    sigprocmask(SIG_BLOCK, &set, &old_);
  }
  ~SignalsBlocked() { sigprocmask(SIG_SETMASK, &old_, nullptr); }

 private:
  sigset_t old_;
};

extern "C" void removeTemporariesAndDie(int signal) {
  for (const std::string& t : g_temporaries) ::unlink(t.c_str());  // async-signal-safe
  ::signal(signal, SIG_DFL);
  ::raise(signal);
}

void watchSignals() {
  if (g_users++ > 0) return;
  struct sigaction action {};
  action.sa_handler = removeTemporariesAndDie;
  sigemptyset(&action.sa_mask);
  for (const int s : kFatalSignals) sigaddset(&action.sa_mask, s);
  for (size_t i = 0; i < 3; ++i) sigaction(kFatalSignals[i], &action, &g_previous[i]);
}

void unwatchSignals() {
  if (--g_users > 0) return;
  for (size_t i = 0; i < 3; ++i) sigaction(kFatalSignals[i], &g_previous[i], nullptr);
}

// --- Names -----------------------------------------------------------------------------

// Markers users do not write: the clean-up after dead runs touches only names with them.
const std::string kTemporaryTag = ndtom::kTemporaryMarker, kAsideTag = ".ndtom-old-";

std::string asidePathFor(const std::string& path) {
  return path + kAsideTag + std::to_string(::getpid());
}

// The pid at the end of `name` after `tag` ("map.ndtom.ndtom-tmp-123" -> 123), or -1.
long pidAfter(const std::string& name, const std::string& tag) {
  const size_t at = name.rfind(tag);
  if (at == std::string::npos || at + tag.size() == name.size()) return -1;
  const std::string digits = name.substr(at + tag.size());
  if (digits.find_first_not_of("0123456789") != std::string::npos || digits.size() > 9) return -1;
  return std::stol(digits);
}

bool processGone(long pid) {
  return pid > 0 && ::kill(pid_t(pid), 0) != 0 && errno == ESRCH;
}

// Temporaries and moved-aside outputs of finished runs with this prefix: removed, or put back
// where a killed commit left an output missing.
void cleanUpAfterDeadRuns(const std::string& prefix) {
  const fs::path base(prefix);
  const fs::path folder = base.parent_path().empty() ? fs::path(".") : base.parent_path();
  const std::string stem = base.filename().string() + ".";
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(folder, ec)) {
    const std::string name = entry.path().filename().string();
    if (name.rfind(stem, 0) != 0) continue;
    if (processGone(pidAfter(name, kTemporaryTag))) {
      fs::remove(entry.path(), ec);
    } else if (processGone(pidAfter(name, kAsideTag))) {
      const fs::path output = folder / name.substr(0, name.rfind(kAsideTag));
      if (fs::exists(fs::symlink_status(output, ec)))
        fs::remove(entry.path(), ec);
      else
        fs::rename(entry.path(), output, ec);
    }
  }
}

[[noreturn]] void failWith(const std::string& what, const std::string& path, int err) {
  throw std::runtime_error(what + " " + path + ": " + std::strerror(err));
}

}  // namespace

OutputFiles::OutputFiles(const std::string& prefix) : prefix_(prefix) {
  const fs::path folder = fs::path(prefix).parent_path();
  std::error_code ec;
  if (!folder.empty()) fs::create_directories(folder, ec);
  if (ec || (!folder.empty() && !fs::is_directory(folder)))
    throw apps::UsageError("-o " + prefix + ": cannot create the folder " + folder.string());
  cleanUpAfterDeadRuns(prefix);
  watchSignals();
}

OutputFiles::~OutputFiles() {
  {
    SignalsBlocked blocked;
    if (!committed_)
      for (const std::string& t : g_temporaries) ::unlink(t.c_str());
    g_temporaries.clear();
  }
  unwatchSignals();
}

std::string OutputFiles::stage(const std::string& role, const std::string& suffix) {
  const std::string path = prefix_ + suffix;
  const std::string temporary = ndtom::temporaryPathFor(path);
  SignalsBlocked blocked;
  files_.push_back({role, path});
  g_temporaries.push_back(temporary);
  return temporary;
}

std::string OutputFiles::write(const std::string& role, const std::string& suffix,
                               const ndtom::FileFiller& fill) {
  ndtom::writeFileSynced(stage(role, suffix), fill);
  return files_.back().path;
}

std::string OutputFiles::writeBytes(const std::string& role, const std::string& suffix,
                                    const std::string& bytes) {
  return write(role, suffix,
               [&](const ndtom::FileSink& sink) { sink(bytes.data(), bytes.size()); });
}

void OutputFiles::commit() {
  SignalsBlocked blocked;  // a signal now would leave a mix: it waits for the outcome
  for (const WrittenFile& f : files_) {
    struct stat st;
    if (::lstat(f.path.c_str(), &st) == 0 && S_ISDIR(st.st_mode))
      throw std::runtime_error("cannot replace " + f.path + ": a folder");
  }
  // Each output: the previous one aside (if any), then the new one in its place.
  std::vector<bool> had_previous(files_.size(), false);
  size_t placed = 0;
  try {
    for (; placed < files_.size(); ++placed) {
      const std::string& path = files_[placed].path;
      if (std::rename(path.c_str(), asidePathFor(path).c_str()) == 0)
        had_previous[placed] = true;
      else if (errno != ENOENT)
        failWith("cannot replace", path, errno);
      if (std::rename(g_temporaries[placed].c_str(), path.c_str()) != 0) {
        const int err = errno;
        if (had_previous[placed]) std::rename(asidePathFor(path).c_str(), path.c_str());
        failWith("cannot replace", path, err);
      }
    }
  } catch (...) {
    for (size_t i = placed; i-- > 0;) {  // back as before, newest first
      const std::string& path = files_[i].path;
      if (had_previous[i])
        std::rename(asidePathFor(path).c_str(), path.c_str());
      else
        ::unlink(path.c_str());
    }
    throw;
  }
  for (size_t i = 0; i < files_.size(); ++i)
    if (had_previous[i]) ::unlink(asidePathFor(files_[i].path).c_str());
  committed_ = true;
  g_temporaries.clear();
}

void writeFileList(JsonWriter& j, const std::vector<WrittenFile>& files) {
  j.beginObject("files");
  for (const WrittenFile& f : files) j.field(f.role, f.path);
  j.endObject();
}

}  // namespace ndtom::apps
