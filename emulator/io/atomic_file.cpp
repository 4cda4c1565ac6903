#include "io/atomic_file.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <string>
#include <system_error>
#include <utility>

namespace dxlemu::io {
namespace {

[[noreturn]] void fail(const std::string& what) {
  throw std::system_error(errno, std::generic_category(), what);
}

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

}  // namespace

void write_file_atomically(const std::filesystem::path& path, std::string_view content) {
  // Same directory, so rename() is atomic; the pid keeps two daemons from sharing a temp file.
  TempFile temp{path.string() + ".tmp." + std::to_string(::getpid())};
  temp.fd = ::open(temp.path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (temp.fd < 0) {
    fail("cannot create " + temp.path);
  }
  while (!content.empty()) {
    const ssize_t n = ::write(temp.fd, content.data(), content.size());
    if (n < 0 && errno == EINTR) {
      continue;
    }
    if (n < 0) {
      fail("cannot write " + temp.path);
    }
    content.remove_prefix(static_cast<std::size_t>(n));
  }
  // Without fsync a power loss could leave the renamed file empty on some file systems.
  if (::fsync(temp.fd) != 0) {
    fail("cannot flush " + temp.path);
  }
  if (::rename(temp.path.c_str(), path.c_str()) != 0) {
    fail("cannot rename " + temp.path + " to " + path.string());
  }
  temp.renamed = true;
}

}  // namespace dxlemu::io
