// The folder an out-of-core build spills its tiles into: PREFIX's name + ".spill-PID", in
// --spill-dir or beside the outputs; created for the run and removed with everything in it
// at its end. Folders of killed runs (their process gone) are removed by the next run there.
#pragma once

#include <string>

namespace ndtom::mapper {

class SpillFolder {
 public:
  /// `dir` empty: PREFIX's folder (created if missing). Throws apps::UsageError naming the
  /// option and the folder if it is a file, cannot be created or is not writable.
  SpillFolder(const std::string& prefix, const std::string& dir);
  ~SpillFolder();
  SpillFolder(const SpillFolder&) = delete;
  SpillFolder& operator=(const SpillFolder&) = delete;

  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

}  // namespace ndtom::mapper
