// Runs one program on one hostile input in a child process: exit status or fatal signal,
// whether it overran its time, its peak resident memory, and what it printed.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace redteam {

struct RunLimits {
  double timeout_s = 60;                       ///< killed after this: a hang
  uint64_t address_space = uint64_t(6) << 30;  ///< RLIMIT_AS: the old code would take 27 GB
  uint64_t file_size = 0;                      ///< RLIMIT_FSIZE if > 0 (a full disk)
  double signal_after_s = -1;                  ///< send `signal` after this (if >= 0)
  int signal = 0;
};

struct Outcome {
  int exit_code = -1;  ///< -1 if it did not exit
  int signal = 0;      ///< the signal that ended it (not ours), 0 if none
  bool timed_out = false;
  bool signalled_by_us = false;
  uint64_t peak_rss = 0;  ///< bytes: the child's VmHWM, sampled every 5 ms until it exits
  double seconds = 0;
  std::string out, err;
};

/// Whether runCommand applies RunLimits::address_space (default on). Off under the sanitizers,
/// whose shadow memory needs terabytes of address space: every child, setups included; ASan's
/// hard_rss_limit_mb (2 GB) bounds them instead.
void limitAddressSpace(bool on);

/// Runs argv[0] with arguments argv[1..] (no shell), in folder `cwd` (if not empty).
Outcome runCommand(const std::vector<std::string>& argv, const RunLimits& limits = {},
                   const std::string& cwd = "");

/// Number of lines of `text` (a final line without '\n' counts).
int lineCount(const std::string& text);

}  // namespace redteam
