#include "app/cli/exec_setup.hpp"

#include <algorithm>
#include <stdexcept>
#include <string_view>

namespace dxlemu::app {
namespace {

namespace fs = std::filesystem;

// A path DXLEMU_PTYS can carry: absolute (the client may change directory), no ':'.
void check_listable(const std::string& path, const std::string& origin) {
  if (path.empty() || path.front() != '/') {
    throw std::invalid_argument(origin + ": \"" + path + "\" is not an absolute path");
  }
  if (path.find(':') != std::string::npos) {
    throw std::invalid_argument(origin + ": \"" + path +
                                "\" holds a ':', which separates the paths of DXLEMU_PTYS");
  }
}

void add_unique(std::vector<std::string>& paths, const std::string& path) {
  if (std::find(paths.begin(), paths.end(), path) == paths.end()) {
    paths.push_back(path);
  }
}

// The pty and link of every port of a `list` result.
void add_listed(std::vector<std::string>& paths, const nlohmann::json& listing,
                const fs::path& socket) {
  const std::string origin = "the daemon at " + socket.string();
  if (!listing.is_object() || !listing.contains("ports") || !listing["ports"].is_array() ||
      listing["ports"].empty()) {
    throw std::invalid_argument(origin + " reports no ports");
  }
  for (const auto& port : listing["ports"]) {
    for (const char* key : {"pty", "link"}) {
      if (port.contains(key) && port[key].is_string()) {
        const std::string path = port[key].get<std::string>();
        check_listable(path, origin);
        add_unique(paths, path);
      }
    }
  }
}

}  // namespace

std::vector<std::string> exec_pty_paths(const ExecArguments& arguments, const fs::path& dir,
                                        const LiveSocketFinder& find, const PortLister& list,
                                        const CharacterDeviceTest& is_character_device) {
  std::vector<std::string> paths;
  for (const std::string& port : arguments.ports) {
    // Made absolute here: the client may change directory, and DXLEMU_PTYS wants '/'.
    const std::string path = fs::absolute(port).lexically_normal().string();
    if (!is_character_device(path)) {
      throw std::invalid_argument("--port " + port +
                                  ": not a character device (a dxlemu PTY or its link)");
    }
    check_listable(path, "--port " + port);
    add_unique(paths, path);
  }
  std::vector<fs::path> sockets = arguments.controls;
  if (arguments.ports.empty() && sockets.empty()) {
    sockets = find(dir);
    if (sockets.empty()) {
      throw std::invalid_argument(
          "no dxlemu PTY to protect: no running dxlemu found (no live "
          "control socket " +
          (dir / "dxlemu-*.sock").string() + "); pass --port PATH or --control SOCKET");
    }
  }
  for (const fs::path& socket : sockets) {
    add_listed(paths, list(socket), socket);
  }
  return paths;
}

fs::path preload_library(const char* override_path, const fs::path& exe_dir,
                         const fs::path& bindir_to_preloaddir,
                         const std::function<bool(const fs::path&)>& exists) {
  const auto usable = [](const fs::path& path) {
    const std::string text = path.string();
    // ld.so splits LD_PRELOAD at both.
    if (text.find_first_of(": ") != std::string::npos) {
      throw std::runtime_error("the preload library's path " + text +
                               " holds a ':' or a space, which LD_PRELOAD cannot carry");
    }
    return path;
  };
  if (override_path != nullptr && *override_path != '\0') {
    const fs::path path = fs::absolute(override_path).lexically_normal();
    if (!exists(path)) {
      throw std::runtime_error("DXLEMU_PRELOAD names " + path.string() + ", which does not exist");
    }
    return usable(path);
  }
  const std::vector<fs::path> candidates = {
      exe_dir / kPreloadLibraryName,
      (exe_dir / bindir_to_preloaddir / kPreloadLibraryName).lexically_normal()};
  std::string looked;
  for (const fs::path& candidate : candidates) {
    if (exists(candidate)) {
      return usable(candidate);
    }
    looked += (looked.empty() ? "" : ", ") + candidate.string();
  }
  throw std::runtime_error(std::string("the preload library ") + kPreloadLibraryName +
                           " was not found (looked at " + looked +
                           "); set DXLEMU_PRELOAD to its path");
}

std::string append_to_list(const char* existing, const std::vector<std::string>& added) {
  std::vector<std::string> items;
  std::string text = existing != nullptr ? existing : "";
  for (std::size_t start = 0; start <= text.size();) {
    const std::size_t end = std::min(text.find(':', start), text.size());
    if (end > start) {
      add_unique(items, text.substr(start, end - start));
    }
    start = end + 1;
  }
  for (const std::string& item : added) {
    add_unique(items, item);
  }
  std::string out;
  for (const std::string& item : items) {
    out += (out.empty() ? "" : ":") + item;
  }
  return out;
}

int exec_split(int argc, const char* const* argv, std::vector<std::string>& command) {
  if (argc < 2 || std::string_view(argv[1]) != "exec") {
    return argc;
  }
  for (int i = 2; i < argc; ++i) {
    if (std::string_view(argv[i]) == "--") {
      command.assign(argv + i + 1, argv + argc);
      return i;
    }
  }
  return argc;
}

}  // namespace dxlemu::app
