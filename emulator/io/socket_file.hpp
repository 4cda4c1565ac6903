#pragma once

#include <sys/stat.h>
#include <sys/types.h>

#include <filesystem>
#include <optional>
#include <string>

// The file of a listening Unix-domain socket: made room for, restricted to its owner, and
// removed only while it is still the one this process made. Used by ControlServer.
namespace dxlemu::io {

/// Owner read and write: only the user who started dxlemu may connect.
inline constexpr mode_t kSocketMode = S_IRUSR | S_IWUSR;

/// "control socket <path>", for messages.
std::string describe_socket(const std::filesystem::path& path);

/// Makes `path` ready for bind(): it must fit a sockaddr_un, and a socket file nobody listens on
/// (left by a server that crashed) is removed. Throws std::system_error naming the path when
/// the path is empty or too long, when another kind of file is there, or when a server listens
/// on it. The probe is a non-blocking connect: it never waits for a live server.
void prepare_socket_path(const std::filesystem::path& path);

/// Which file a path named when it was looked at.
struct FileIdentity {
  dev_t device = 0;
  ino_t inode = 0;
};

/// Gives the socket file just bound at `path` kSocketMode and returns which file it is; nullopt
/// when either step fails (errno says why).
std::optional<FileIdentity> restrict_socket_file(const std::filesystem::path& path);

/// Removes `path` if it is still the file `identity` names (and leaves alone whatever another
/// server has put there since).
void remove_if_same(const std::filesystem::path& path, const FileIdentity& identity);

}  // namespace dxlemu::io
