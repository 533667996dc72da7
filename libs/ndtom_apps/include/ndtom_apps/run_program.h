// What every program's main() does with a failure: one line "program: message" on stderr, and
// an exit status that scripts can tell apart: 2 for a bad command line or configuration
// (UsageError), 1 for anything else (unreadable input, a failed write).
#pragma once

#include <exception>
#include <functional>
#include <string>

namespace ndtom::apps {

/// Runs `body` (read the options, print the help or do the work) and returns its exit
/// status, or 2 after a UsageError and 1 after any other exception, with its message
/// (std::bad_alloc, whose message says nothing, as "out of memory: ..."), or 1 if what it
/// printed could not be written to the standard output (a full disk, say).
int runProgram(const std::string& name, const std::function<int()>& body);

/// The message of an exception on one line: for MRPT's exceptions, whose what() spans a
/// banner, the message, its source location and a backtrace, only the message.
std::string oneLineMessage(const std::exception& e);

}  // namespace ndtom::apps
