#pragma once

#include <filesystem>
#include <string>
#include <string_view>

// Which file a GET names: the web root's files at "/", Debian's JavaScript libraries at "/lib/".
// Lexical checks only (no ".." or hidden names, no NUL or backslash), then the file must be a
// regular file; symbolic links are followed, as Debian's library directories hold some.
namespace dxlemu::io::web {

/// Where a served file comes from (decides its caching).
enum class FileArea { WebRoot, Library };

/// The outcome of resolve_file: a file, or the HTTP status and a short reason to refuse with.
struct FileLookup {
  unsigned status = 200;       ///< 200, or 400 / 404
  std::string reason;          ///< why not, for the response body
  std::filesystem::path file;  ///< when status is 200
  FileArea area = FileArea::WebRoot;
};

/// The library directories served under /lib/ (Debian's libjs-three and libjs-chart.js).
inline constexpr std::string_view kLibraryDirectories[] = {"three", "chart.js"};

/// Resolves a request's path (still %-encoded, without its query): "/" is the web root's
/// index.html, "/lib/three/..." and "/lib/chart.js/..." are under `library_root`, anything else
/// is under `web_root`. Refused: malformed escapes, NUL or backslash (400); empty, "." / ".."
/// or other names starting with '.', other library directories, directories and missing files
/// (404).
FileLookup resolve_file(std::string_view path, const std::filesystem::path& web_root,
                        const std::filesystem::path& library_root);

/// The Content-Type of a served file, by its extension (application/octet-stream when unknown).
std::string_view mime_type(const std::filesystem::path& file);

}  // namespace dxlemu::io::web
