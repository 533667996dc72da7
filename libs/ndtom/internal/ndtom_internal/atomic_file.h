// Whole-file writes that never leave a half-written file under the final name.
#pragma once

#include <cstddef>
#include <functional>
#include <string>

namespace ndtom {

/// Receives a file's bytes in pieces; throws std::runtime_error naming the file if a write
/// fails.
using FileSink = std::function<void(const void* data, size_t size)>;
/// Writes a file's content through the sink it is given.
using FileFiller = std::function<void(const FileSink& write)>;

/// Writes `path`.ndtom-tmp-<pid>, flushes it to disk and renames it over `path`. On any failure the
/// temporary is removed, `path` keeps its previous content, and std::runtime_error names it.
void writeFileAtomically(const std::string& path, const void* data, size_t size);
/// The same, the content written piece by piece by `fill` (no copy of the whole file).
void writeFileAtomically(const std::string& path, const FileFiller& fill);

/// Writes `path` itself (created or truncated) through `fill` and flushes it to disk: for
/// outputs staged under temporary names their caller chose. On failure the file is removed
/// and std::runtime_error names it.
void writeFileSynced(const std::string& path, const FileFiller& fill);

/// Flushes a file written by other code (e.g. another library) to disk; throws
/// std::runtime_error naming it on failure.
void syncFile(const std::string& path);

/// Renames `from` over `to` (same filesystem), throwing std::runtime_error on failure.
void renameFile(const std::string& from, const std::string& to);

/// What marks a temporary in its name. Clean-up after killed runs removes only names with a
/// marker users do not write: "run.ndtom.tmp-20241203" may be someone's file.
inline constexpr const char* kTemporaryMarker = ".ndtom-tmp-";
/// The temporary name writeFileAtomically uses for `path`: `path` + marker + pid.
std::string temporaryPathFor(const std::string& path);

}  // namespace ndtom
