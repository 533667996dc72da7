// The files of a run, written under temporary names and renamed into place together at the
// end: a run that fails or is interrupted leaves no file that looks complete.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "run_summary.h"

namespace ndtom::mapper {

class OutputFiles {
 public:
  /// Outputs are PREFIX + suffix. Creates PREFIX's folder if needed; throws apps::UsageError if it
  /// cannot.
  explicit OutputFiles(const std::string& prefix);
  /// Removes the temporaries of a set that was not committed.
  ~OutputFiles();
  OutputFiles(const OutputFiles&) = delete;
  OutputFiles& operator=(const OutputFiles&) = delete;

  /// Registers PREFIX + suffix under `role` and returns the temporary path to write it to.
  std::string stage(const std::string& role, const std::string& suffix);
  /// Writes `bytes` to the temporary of a new output (flushed to disk); returns its final path.
  std::string writeBytes(const std::string& role, const std::string& suffix,
                         const std::string& bytes);

  /// Renames every temporary to its final name. Throws std::runtime_error naming a file.
  void commit();

  /// The outputs so far, by role, under their final names.
  const std::vector<WrittenFile>& files() const { return files_; }

 private:
  std::string prefix_;
  std::vector<WrittenFile> files_;
  std::vector<std::string> temporaries_;
  bool committed_ = false;
};

}  // namespace ndtom::mapper
