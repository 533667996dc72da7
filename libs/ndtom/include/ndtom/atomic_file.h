// Whole-file writes that never leave a half-written file under the final name.
#pragma once

#include <cstddef>
#include <string>

namespace ndtom {

/// Writes `path`.tmp-<pid>, flushes it to disk and renames it over `path`. On any failure the
/// temporary is removed, `path` keeps its previous content, and std::runtime_error names it.
void writeFileAtomically(const std::string& path, const void* data, size_t size);

/// Renames `from` over `to` (same filesystem), throwing std::runtime_error on failure.
void renameFile(const std::string& from, const std::string& to);

/// The temporary name writeFileAtomically uses for `path`.
std::string temporaryPathFor(const std::string& path);

}  // namespace ndtom
