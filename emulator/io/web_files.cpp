#include "io/web_files.hpp"

#include <algorithm>
#include <cctype>
#include <optional>
#include <system_error>
#include <utility>
#include <vector>

#include "io/web_access.hpp"

namespace dxlemu::io::web {
namespace files_detail {

FileLookup refuse(unsigned status, std::string reason) {
  FileLookup lookup;
  lookup.status = status;
  lookup.reason = std::move(reason);
  return lookup;
}

}  // namespace files_detail

using namespace files_detail;  // NOLINT: this file's helpers, named for the unity build

FileLookup resolve_file(std::string_view path, const std::filesystem::path& web_root,
                        const std::filesystem::path& library_root) {
  const std::optional<std::string> decoded = percent_decode(path);
  if (!decoded) {
    return refuse(400, "malformed %-escape in the path");
  }
  if (decoded->find('\0') != std::string::npos || decoded->find('\\') != std::string::npos) {
    return refuse(400, "NUL or backslash in the path");
  }
  if (decoded->empty() || decoded->front() != '/') {
    return refuse(400, "the path does not start with '/'");
  }
  std::vector<std::string_view> names;
  std::string_view rest = std::string_view(*decoded).substr(1);
  if (rest.empty()) {
    names.emplace_back("index.html");
  }
  while (!rest.empty()) {
    const std::size_t slash = rest.find('/');
    names.push_back(rest.substr(0, slash));
    rest.remove_prefix(slash == std::string_view::npos ? rest.size() : slash + 1);
    if (slash != std::string_view::npos && rest.empty()) {
      names.emplace_back();  // a trailing '/': a directory, not served
    }
  }
  // Hidden names and "." / "..": nothing of ours starts with '.', and refusing them all keeps
  // every path under its root without looking at the file system.
  for (const std::string_view name : names) {
    if (name.empty() || name.front() == '.') {
      return refuse(404, "not found");
    }
  }
  FileLookup lookup;
  std::filesystem::path file;
  if (names.front() == "lib") {
    if (names.size() < 3 ||
        std::find(std::begin(kLibraryDirectories), std::end(kLibraryDirectories), names[1]) ==
            std::end(kLibraryDirectories)) {
      return refuse(404, "not found");
    }
    lookup.area = FileArea::Library;
    file = library_root;
    names.erase(names.begin());
  } else {
    file = web_root;
  }
  for (const std::string_view name : names) {
    file /= name;
  }
  std::error_code ec;
  if (!std::filesystem::is_regular_file(file, ec)) {
    return refuse(404, "not found");
  }
  lookup.file = std::move(file);
  return lookup;
}

std::string_view mime_type(const std::filesystem::path& file) {
  std::string extension = file.extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  static constexpr std::pair<std::string_view, std::string_view> kTypes[] = {
      {".html", "text/html; charset=utf-8"},
      {".js", "text/javascript; charset=utf-8"},
      {".mjs", "text/javascript; charset=utf-8"},
      {".css", "text/css; charset=utf-8"},
      {".json", "application/json"},
      {".map", "application/json"},
      {".png", "image/png"},
      {".svg", "image/svg+xml"},
      {".ico", "image/x-icon"},
      {".txt", "text/plain; charset=utf-8"},
  };
  for (const auto& [ext, type] : kTypes) {
    if (extension == ext) {
      return type;
    }
  }
  return "application/octet-stream";
}

}  // namespace dxlemu::io::web
