#include "app/cli/exec_command.hpp"

#include <sys/stat.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>

#include "app/cli/exit_status.hpp"
#include "app/daemon/run_options.hpp"
#include "io/child_process.hpp"
#include "io/control_client.hpp"

namespace dxlemu::app {
namespace {

// How long `dxlemu exec` waits for a daemon's port list.
constexpr std::chrono::seconds kExecListTimeout{5};

// The `list` result of the daemon at `socket`; throws naming the socket when it refuses.
nlohmann::json list_ports(const std::filesystem::path& socket) {
  io::ControlClient client(socket);
  const auto reply = nlohmann::json::parse(
      client.call(R"({"id": 1, "cmd": "list"})", kExecListTimeout), nullptr, false);
  if (!reply.is_object() || !reply.value("ok", false)) {
    throw std::runtime_error("the daemon at " + socket.string() + " did not list its ports: " +
                             (reply.is_object() ? reply.value("error", reply.dump()) : "no reply"));
  }
  return reply["result"];
}

bool is_character_device(const std::filesystem::path& path) {
  struct stat status {};
  return ::stat(path.c_str(), &status) == 0 && S_ISCHR(status.st_mode);
}

}  // namespace

int run_exec(const ExecArguments& arguments) {
  std::map<std::string, std::string> environment;
  try {
    std::error_code error;
    const auto exe = std::filesystem::read_symlink("/proc/self/exe", error);
    const auto library =
        preload_library(std::getenv("DXLEMU_PRELOAD"), exe.parent_path(),
                        DXLEMU_BINDIR_TO_PRELOADDIR, [](const std::filesystem::path& path) {
                          std::error_code ignored;
                          return std::filesystem::is_regular_file(path, ignored);
                        });
    const auto dir = default_control_path().parent_path();
    const auto paths =
        exec_pty_paths(arguments, dir, io::live_control_sockets, list_ports, is_character_device);
    environment["LD_PRELOAD"] = append_to_list(std::getenv("LD_PRELOAD"), {library.string()});
    environment["DXLEMU_PTYS"] = append_to_list(std::getenv("DXLEMU_PTYS"), paths);
  } catch (const std::exception& e) {
    std::cerr << "dxlemu exec: " << e.what() << "\n";
    return kExitExecFailed;
  }
  try {
    return io::run_child(arguments.command, environment);
  } catch (const std::exception& e) {
    std::cerr << "dxlemu exec: " << e.what() << "\n";
    return kExitExecFailed;
  }
}

}  // namespace dxlemu::app
