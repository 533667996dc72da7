#include "output_files.h"

#include <cstdio>
#include <filesystem>

#include "ndtom/atomic_file.h"
#include "ndtom_apps/option_values.h"

namespace fs = std::filesystem;

namespace ndtom::mapper {

OutputFiles::OutputFiles(const std::string& prefix) : prefix_(prefix) {
  const fs::path folder = fs::path(prefix).parent_path();
  std::error_code ec;
  if (!folder.empty()) fs::create_directories(folder, ec);
  if (ec || (!folder.empty() && !fs::is_directory(folder)))
    throw apps::UsageError("-o " + prefix + ": cannot create the folder " + folder.string());
}

OutputFiles::~OutputFiles() {
  if (committed_) return;
  for (const std::string& t : temporaries_) std::remove(t.c_str());
}

std::string OutputFiles::stage(const std::string& role, const std::string& suffix) {
  const std::string path = prefix_ + suffix;
  files_.push_back({role, path});
  temporaries_.push_back(ndtom::temporaryPathFor(path));
  return temporaries_.back();
}

std::string OutputFiles::writeBytes(const std::string& role, const std::string& suffix,
                                    const std::string& bytes) {
  const std::string temporary = stage(role, suffix);
  // Atomic onto the temporary name too: flushed to disk before the final rename.
  ndtom::writeFileAtomically(temporary, bytes.data(), bytes.size());
  return files_.back().path;
}

void OutputFiles::commit() {
  for (size_t i = 0; i < files_.size(); ++i) ndtom::renameFile(temporaries_[i], files_[i].path);
  committed_ = true;
}

}  // namespace ndtom::mapper
