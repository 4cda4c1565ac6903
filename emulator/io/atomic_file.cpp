#include "io/atomic_file.hpp"

#include <fcntl.h>
#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <mutex>
#include <set>
#include <string>
#include <system_error>
#include <utility>

#include "io/errno_error.hpp"

namespace dxlemu::io {
namespace {

// Closes the descriptor on every path out, and removes the temporary file unless renamed.
struct TempFile {
  std::string path;
  int fd = -1;
  bool renamed = false;
  explicit TempFile(std::string p) : path(std::move(p)) {}
  TempFile(const TempFile&) = delete;
  TempFile& operator=(const TempFile&) = delete;
  ~TempFile() {
    if (fd >= 0) {
      ::close(fd);
    }
    if (!renamed) {
      ::unlink(path.c_str());
    }
  }
};

std::filesystem::path directory_of(const std::filesystem::path& path) {
  return path.has_parent_path() ? path.parent_path() : std::filesystem::path(".");
}

// A daemon killed while it saved leaves its temporary file (PATH.tmp.PID) behind. The first save
// of a path in a process removes those whose process is gone; a live one may be mid-save.
void remove_stale_temp_files(const std::filesystem::path& path) {
  static std::mutex mutex;
  static std::set<std::filesystem::path> done;
  const std::scoped_lock lock(mutex);
  if (!done.insert(path).second) {
    return;
  }
  const std::string prefix = path.filename().string() + ".tmp.";
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator(directory_of(path), ec)) {
    const std::string name = entry.path().filename().string();
    const std::string pid = name.substr(std::min(prefix.size(), name.size()));
    if (!name.starts_with(prefix) || pid.empty() || pid.size() > 9 ||
        !std::all_of(pid.begin(), pid.end(), [](unsigned char c) { return std::isdigit(c); })) {
      continue;
    }
    if (::kill(static_cast<pid_t>(std::stol(pid)), 0) != 0 && errno == ESRCH) {
      std::filesystem::remove(entry.path(), ec);
    }
  }
}

}  // namespace

void write_file_atomically(const std::filesystem::path& path, std::string_view content) {
  remove_stale_temp_files(path);
  // Same directory, so rename() is atomic; the pid keeps two daemons from sharing a temp file.
  TempFile temp{path.string() + ".tmp." + std::to_string(::getpid())};
  temp.fd = ::open(temp.path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (temp.fd < 0) {
    throw_errno("cannot create " + temp.path);
  }
  while (!content.empty()) {
    const ssize_t n = ::write(temp.fd, content.data(), content.size());
    if (n < 0 && errno == EINTR) {
      continue;
    }
    if (n < 0) {
      throw_errno("cannot write " + temp.path);
    }
    content.remove_prefix(static_cast<std::size_t>(n));
  }
  // Without fsync a power loss could leave the renamed file empty on some file systems.
  if (::fsync(temp.fd) != 0) {
    throw_errno("cannot flush " + temp.path);
  }
  if (::rename(temp.path.c_str(), path.c_str()) != 0) {
    throw_errno("cannot rename " + temp.path + " to " + path.string());
  }
  temp.renamed = true;
  // The rename is an entry in the directory: flush it too, or a power loss could bring back the
  // old file. Best effort: some file systems cannot flush a directory, and the new file is in
  // place either way.
  const int directory = ::open(directory_of(path).c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (directory >= 0) {
    ::fsync(directory);
    ::close(directory);
  }
}

}  // namespace dxlemu::io
