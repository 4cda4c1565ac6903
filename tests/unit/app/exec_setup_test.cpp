// `dxlemu exec` (docs/exec.md): which PTYs it protects, where it finds the preload library, the
// environment lists it extends and how its command line splits.
#include <catch2/catch.hpp>
#include <stdexcept>

#include "app/cli/exec_setup.hpp"
#include "live_sockets.hpp"

using namespace dxlemu;
namespace fs = std::filesystem;
using Paths = std::vector<std::string>;

namespace {

using test::finding;

const fs::path kDir = "/run/user/1000";

// A daemon per socket: dxl0 at /dev/pts/N with link /tmp/dxlN, N the socket's number.
nlohmann::json listing(const fs::path& socket) {
  const std::string n = socket.stem().string().substr(std::string("dxlemu-").size());
  return {{"ports", {{{"name", "dxl0"}, {"pty", "/dev/pts/" + n}, {"link", "/tmp/dxl" + n}}}}};
}

bool every_path_a_device(const fs::path&) {
  return true;
}

Paths paths_of(const app::ExecArguments& arguments, const std::vector<fs::path>& live = {}) {
  return app::exec_pty_paths(arguments, kDir, finding(live), listing, every_path_a_device);
}

std::string exec_refusal(const app::ExecArguments& arguments,
                         const app::CharacterDeviceTest& device,
                         const app::PortLister& list = listing) {
  try {
    app::exec_pty_paths(arguments, kDir, finding({}), list, device);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "accepted";
}

bool exists_in(const std::vector<fs::path>& files, const fs::path& path) {
  return std::find(files.begin(), files.end(), path) != files.end();
}

std::string library_refusal(const char* override_path, const std::vector<fs::path>& files) {
  try {
    app::preload_library(override_path, "/opt/x/bin", "../lib/dxlemu",
                         [&](const fs::path& p) { return exists_in(files, p); });
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "accepted";
}

}  // namespace

TEST_CASE("exec protects every --port and the ports of every --control daemon, once each",
          "[app][exec]") {
  app::ExecArguments arguments;
  arguments.ports = {"/tmp/dxl7", "/dev/pts/9"};
  arguments.controls = {"/s/dxlemu-7.sock", "/s/dxlemu-8.sock"};
  CHECK(paths_of(arguments) ==
        Paths{"/tmp/dxl7", "/dev/pts/9", "/dev/pts/7", "/dev/pts/8", "/tmp/dxl8"});
}

TEST_CASE("exec without --port or --control protects the ports of every running daemon",
          "[app][exec]") {
  CHECK(paths_of({}, {kDir / "dxlemu-3.sock", kDir / "dxlemu-4.sock"}) ==
        Paths{"/dev/pts/3", "/tmp/dxl3", "/dev/pts/4", "/tmp/dxl4"});
  CHECK(exec_refusal({}, every_path_a_device) ==
        "no dxlemu PTY to protect: no running dxlemu found (no live control socket "
        "/run/user/1000/dxlemu-*.sock); pass --port PATH or --control SOCKET");
}

TEST_CASE("exec refuses a --port that is no character device or that DXLEMU_PTYS cannot carry",
          "[app][exec]") {
  app::ExecArguments arguments;
  arguments.ports = {"/tmp/missing"};
  CHECK(exec_refusal(arguments, [](const fs::path&) { return false; }) ==
        "--port /tmp/missing: not a character device (a dxlemu PTY or its link)");
  arguments.ports = {"/tmp/a:b"};
  CHECK(exec_refusal(arguments, every_path_a_device) ==
        "--port /tmp/a:b: \"/tmp/a:b\" holds a ':', which separates the paths of DXLEMU_PTYS");
  // A relative --port is made absolute: the client may change directory.
  arguments.ports = {"dxl0"};
  CHECK(paths_of(arguments) == Paths{(fs::current_path() / "dxl0").string()});
}

TEST_CASE("exec refuses a daemon that lists no ports", "[app][exec]") {
  app::ExecArguments arguments;
  arguments.controls = {"/s/dxlemu-1.sock"};
  CHECK(exec_refusal(arguments, every_path_a_device, [](const fs::path&) {
          return nlohmann::json{{"ports", nlohmann::json::array()}};
        }) == "the daemon at /s/dxlemu-1.sock reports no ports");
}

TEST_CASE("The preload library is DXLEMU_PRELOAD, else next to the binary, else installed",
          "[app][exec]") {
  const auto find = [](const char* override_path, const std::vector<fs::path>& files) {
    return app::preload_library(override_path, "/opt/x/bin", "../lib/dxlemu",
                                [&](const fs::path& p) { return exists_in(files, p); });
  };
  const fs::path beside = "/opt/x/bin/libdxlemu-preload.so";
  const fs::path installed = "/opt/x/lib/dxlemu/libdxlemu-preload.so";
  CHECK(find("/my/lib.so", {"/my/lib.so", beside}) == "/my/lib.so");
  CHECK(find("", {beside, installed}) == beside);
  CHECK(find(nullptr, {installed}) == installed);
  CHECK(library_refusal(nullptr, {}) ==
        "the preload library libdxlemu-preload.so was not found (looked at "
        "/opt/x/bin/libdxlemu-preload.so, /opt/x/lib/dxlemu/libdxlemu-preload.so); set "
        "DXLEMU_PRELOAD to its path");
  CHECK(library_refusal("/my/lib.so", {beside}) ==
        "DXLEMU_PRELOAD names /my/lib.so, which does not exist");
  CHECK(library_refusal("/my lib.so", {"/my lib.so"}) ==
        "the preload library's path /my lib.so holds a ':' or a space, which LD_PRELOAD cannot "
        "carry");
}

TEST_CASE("LD_PRELOAD and DXLEMU_PTYS keep what they had and gain each new element once",
          "[app][exec]") {
  CHECK(app::append_to_list(nullptr, {"/a.so"}) == "/a.so");
  CHECK(app::append_to_list("", {"/a.so"}) == "/a.so");
  CHECK(app::append_to_list("/x.so::/a.so", {"/a.so", "/b.so"}) == "/x.so:/a.so:/b.so");
}

TEST_CASE("exec's COMMAND is what follows its first --, and only exec's", "[app][exec]") {
  const char* with_dashes[] = {"dxlemu", "exec", "--port", "/p", "--", "sh", "-c", "--"};
  std::vector<std::string> command;
  CHECK(app::exec_split(8, with_dashes, command) == 4);
  CHECK(command == Paths{"sh", "-c", "--"});
  const char* ctl[] = {"dxlemu", "ctl", "--", "x"};
  command.clear();
  CHECK(app::exec_split(4, ctl, command) == 4);
  CHECK(command.empty());
}
