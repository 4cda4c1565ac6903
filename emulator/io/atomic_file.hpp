#pragma once

#include <filesystem>
#include <string_view>

namespace dxlemu::io {

/// Replaces `path` with `content` so that a reader, or a crash at any moment, sees either the
/// old file or the new one, never a mixture: the content goes to a temporary file in the same
/// directory, is flushed to disk, and is renamed over `path`; then the directory is flushed. The
/// first call for a path also removes temporary files that killed processes left behind. Throws
/// std::system_error.
void write_file_atomically(const std::filesystem::path& path, std::string_view content);

}  // namespace dxlemu::io
