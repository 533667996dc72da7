// The files of a run, written under temporary names and renamed into place together at the
// end: all of them or none. A run that fails, is interrupted (SIGINT, SIGTERM, SIGHUP) or
// cannot replace one of the previous outputs leaves the previous outputs as they were and no
// temporary behind; temporaries of a run that was killed outright are removed by the next
// run with the same prefix.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "ndtom_internal/atomic_file.h"

namespace ndtom::apps {

struct WrittenFile {
  std::string role;  ///< "map", "mrpt_map", "scene", "top_view", "view_3d", "coarse_map", ...
  std::string path;
};

class JsonWriter;
/// A summary's "files": {"role": "path", ...}, as every program writes it.
void writeFileList(JsonWriter& j, const std::vector<WrittenFile>& files);

class OutputFiles {
 public:
  /// Outputs are PREFIX + suffix. Creates PREFIX's folder if needed (throws apps::UsageError if
  /// it cannot), and cleans up after runs with this prefix whose process is gone: removes
  /// their temporaries, and puts back a previous output a killed commit had moved aside.
  explicit OutputFiles(const std::string& prefix);
  /// Removes the temporaries of a set that was not committed.
  ~OutputFiles();
  OutputFiles(const OutputFiles&) = delete;
  OutputFiles& operator=(const OutputFiles&) = delete;

  /// Registers PREFIX + suffix under `role` and returns the temporary path to write it to.
  std::string stage(const std::string& role, const std::string& suffix);
  /// Writes a new output's temporary through `fill`, flushed to disk; returns its final path.
  std::string write(const std::string& role, const std::string& suffix,
                    const ndtom::FileFiller& fill);
  /// The same with the whole content at hand.
  std::string writeBytes(const std::string& role, const std::string& suffix,
                         const std::string& bytes);

  /// Puts every temporary in place of its output, or none: checks first that each output can
  /// be replaced (not a folder), moves each previous output aside before replacing it, and
  /// on any failure puts back what it moved. Signals that end the program wait until it is
  /// done. Throws std::runtime_error naming the file that could not be replaced.
  void commit();

  /// The outputs so far, by role, under their final names.
  const std::vector<WrittenFile>& files() const { return files_; }

 private:
  std::string prefix_;
  std::vector<WrittenFile> files_;
  bool committed_ = false;
};

}  // namespace ndtom::apps
