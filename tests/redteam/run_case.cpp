#include "run_case.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <fstream>
#include <thread>

namespace redteam {
namespace {

// The peak resident memory of a running process, from /proc (0 once it has exited).
// getrusage() of the child would count the harness's own pages, which the child shares
// between fork() and exec().
uint64_t peakRss(pid_t pid) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/status");
  for (std::string line; std::getline(in, line);)
    if (line.rfind("VmHWM:", 0) == 0) return std::stoull(line.substr(6)) * 1024;
  return 0;
}

// Appends what can be read from non-blocking `fd` now.
void drain(int fd, std::string& into) {
  char buffer[4096];
  for (ssize_t n; (n = read(fd, buffer, sizeof(buffer))) > 0;) into.append(buffer, size_t(n));
}

}  // namespace

int lineCount(const std::string& text) {
  int lines = 0;
  for (const char c : text) lines += c == '\n';
  return lines + (!text.empty() && text.back() != '\n');
}

namespace {
bool address_space_limited = true;
}  // namespace

void limitAddressSpace(bool on) {
  address_space_limited = on;
}

Outcome runCommand(const std::vector<std::string>& argv, const RunLimits& limits,
                   const std::string& cwd) {
  // Pipes, not files: a file-size limit on the child must not cut its messages.
  int out_pipe[2], err_pipe[2];
  if (pipe(out_pipe) != 0 || pipe(err_pipe) != 0) return Outcome{};
  const auto start = std::chrono::steady_clock::now();
  const pid_t pid = fork();
  if (pid == 0) {
    setpgid(0, 0);  // its own group, so that a timeout kills what it started too
    dup2(out_pipe[1], 1);
    dup2(err_pipe[1], 2);
    close(out_pipe[0]);
    close(err_pipe[0]);
    const int null = open("/dev/null", O_RDONLY);
    dup2(null, 0);
    if (address_space_limited) {
      const rlimit as{limits.address_space, limits.address_space};
      setrlimit(RLIMIT_AS, &as);
    } else {
      // Under ASan a bound on resident memory instead (its max_allocation_size is ignored by
      // GCC 12's runtime): else a huge allocation in MRPT's reader is granted and zero-filled,
      // tens of gigabytes. 2 GB: a run over 1.5 GB is a failure anyway.
      const char* inherited = getenv("ASAN_OPTIONS");
      const std::string asan =
          std::string(inherited ? inherited : "") + ":hard_rss_limit_mb=2048:abort_on_error=1";
      setenv("ASAN_OPTIONS", asan.c_str(), 1);
    }
    if (limits.file_size > 0) {
      const rlimit fs{limits.file_size, limits.file_size};
      setrlimit(RLIMIT_FSIZE, &fs);
      signal(SIGXFSZ, SIG_IGN);  // write() fails with EFBIG instead, as on a full disk
    }
    if (!cwd.empty() && chdir(cwd.c_str()) != 0) _exit(127);
    std::vector<char*> args;
    for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
    args.push_back(nullptr);
    execv(args[0], args.data());
    _exit(127);
  }
  close(out_pipe[1]);
  close(err_pipe[1]);
  fcntl(out_pipe[0], F_SETFL, O_NONBLOCK);
  fcntl(err_pipe[0], F_SETFL, O_NONBLOCK);
  Outcome o;
  bool signal_sent = false;
  int status = 0;
  rusage usage{};
  uint64_t peak = 0;
  for (;;) {
    drain(out_pipe[0], o.out);
    drain(err_pipe[0], o.err);
    peak = std::max(peak, peakRss(pid));  // sampled until exit: the peak is a plateau
    const pid_t done = wait4(pid, &status, WNOHANG, &usage);
    if (done == pid) break;
    const double elapsed =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (!signal_sent && limits.signal_after_s >= 0 && elapsed >= limits.signal_after_s) {
      kill(pid, limits.signal);
      signal_sent = true;
    }
    if (elapsed > limits.timeout_s) {
      o.timed_out = true;
      kill(-pid, SIGKILL);
      wait4(pid, &status, 0, &usage);
      break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  o.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  o.peak_rss = peak;
  if (WIFEXITED(status)) o.exit_code = WEXITSTATUS(status);
  if (WIFSIGNALED(status) && !o.timed_out) {
    o.signal = WTERMSIG(status);
    o.signalled_by_us = signal_sent && o.signal == limits.signal;
  }
  drain(out_pipe[0], o.out);
  drain(err_pipe[0], o.err);
  close(out_pipe[0]);
  close(err_pipe[0]);
  return o;
}

}  // namespace redteam
