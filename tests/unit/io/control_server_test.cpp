// ControlServer over a real Unix socket in a temporary directory, its io_context run by hand.
// The kernel moves bytes between Unix sockets at once, so after settle() the server has read
// everything the clients wrote and written what it answered.
#include "io/control_server.hpp"

#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

#include <catch2/catch.hpp>

#include <boost/asio/io_context.hpp>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <stdexcept>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

#include "io_rig.hpp"

namespace {

using dxlemu::io::ControlServer;
using dxlemu::io::ControlSession;
using dxlemu::test::IoTempDir;
using dxlemu::test::settle;
namespace fs = std::filesystem;

ControlServer::Replies replies() {
  return {[](std::size_t limit) { return "too long: " + std::to_string(limit); },
          [](std::string_view what) { return "internal: " + std::string(what); }};
}

// Upper-cases the line; "throw" throws, "quiet" answers nothing, "id" answers the session's id.
std::string answer(std::string_view line, ControlSession& session) {
  if (line == "throw") {
    throw std::runtime_error("boom");
  }
  if (line == "quiet") {
    return {};
  }
  if (line == "id") {
    return std::to_string(session.id());
  }
  std::string out(line);
  for (char& c : out) {
    c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  }
  return out;
}

// A client of the socket at `path`: non-blocking, so reading takes what is there now.
class SocketClient {
 public:
  explicit SocketClient(const fs::path& path)
      : fd_(::socket(AF_UNIX, SOCK_STREAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0)) {
    REQUIRE(fd_ >= 0);
    sockaddr_un address{};
    address.sun_family = AF_UNIX;
    std::strncpy(static_cast<char*>(address.sun_path), path.c_str(), sizeof address.sun_path - 1);
    // NOLINTNEXTLINE(cppcoreguidelines-pro-type-reinterpret-cast): the sockets API
    REQUIRE(::connect(fd_, reinterpret_cast<const sockaddr*>(&address), sizeof address) == 0);
  }
  ~SocketClient() { close(); }
  SocketClient(const SocketClient&) = delete;
  SocketClient& operator=(const SocketClient&) = delete;

  void write(std::string_view bytes) const {
    REQUIRE(::write(fd_, bytes.data(), bytes.size()) == static_cast<ssize_t>(bytes.size()));
  }
  void shutdown_sending() const { REQUIRE(::shutdown(fd_, SHUT_WR) == 0); }
  void close() {
    if (fd_ >= 0) {
      ::close(fd_);
      fd_ = -1;
    }
  }
  // Reads what has arrived; false once the server closed the connection.
  bool read_now() {
    char buffer[65536];
    for (;;) {
      const ssize_t n = ::read(fd_, buffer, sizeof buffer);
      if (n > 0) {
        received_.append(buffer, static_cast<std::size_t>(n));
        continue;
      }
      return n < 0 && errno == EAGAIN;
    }
  }
  // The complete lines received so far and not yet taken, without their newlines.
  std::vector<std::string> lines() {
    read_now();
    std::vector<std::string> out;
    std::size_t newline = 0;
    while ((newline = received_.find('\n')) != std::string::npos) {
      out.push_back(received_.substr(0, newline));
      received_.erase(0, newline + 1);
    }
    return out;
  }
  // Bytes received so far and not yet taken as lines.
  std::size_t unread() {
    read_now();
    return received_.size();
  }
  void forget_received() { received_.clear(); }

 private:
  int fd_;
  std::string received_;
};

using Lines = std::vector<std::string>;

// A server on a socket in a temporary directory, with the sessions it reported closed.
struct Rig {
  explicit Rig(std::size_t max_line = ControlServer::kDefaultMaxLine,
               ControlServer::Handler handler = answer)
      : server(std::make_unique<ControlServer>(io, dir.path() / "ctl.sock", std::move(handler),
                                               replies(), max_line)) {
    server->on_close([this](ControlSession& session) { closed.push_back(session.id()); });
  }
  fs::path path() const { return dir.path() / "ctl.sock"; }

  IoTempDir dir;
  boost::asio::io_context io;
  // Before the server: its destructor reports the sessions still open.
  std::vector<std::uint64_t> closed;
  std::unique_ptr<ControlServer> server;
};

}  // namespace

TEST_CASE("Each request line gets its reply, in order, however the lines are split",
          "[io][control_server]") {
  Rig rig;
  SocketClient client(rig.path());
  client.write("one\ntw");
  settle(rig.io);
  CHECK(client.lines() == Lines{"ONE"});
  client.write("o\nthree\r\n\n\r\nquiet\nfour\n");
  settle(rig.io);
  // "\r\n" ends a line too; empty lines and empty answers get no reply.
  CHECK(client.lines() == Lines{"TWO", "THREE", "FOUR"});
  CHECK(client.unread() == 0);
}

TEST_CASE("An over-long request gets the oversize reply and the connection stays up",
          "[io][control_server]") {
  Rig rig(8);
  SocketClient client(rig.path());
  client.write("12345678\n123456789\n");
  settle(rig.io);
  CHECK(client.lines() == Lines{"12345678", "too long: 8"});
  // The "\r" of "\r\n" does not count; one waiting for its "\n" does not count either.
  client.write("abcdefgh\r");
  settle(rig.io);
  client.write("\n");
  settle(rig.io);
  CHECK(client.lines() == Lines{"ABCDEFGH"});
  // Refused as soon as it is too long; the rest, over several writes, is skipped to its newline.
  client.write("abcdefghi");
  settle(rig.io);
  CHECK(client.lines() == Lines{"too long: 8"});
  client.write("jklmnopqrstuvwxyz");
  settle(rig.io);
  client.write("more\nnext\n");
  settle(rig.io);
  CHECK(client.lines() == Lines{"NEXT"});
  CHECK(rig.server->sessions() == 1);
}

TEST_CASE("A handler that throws gets the internal error reply and the connection stays up",
          "[io][control_server]") {
  Rig rig;
  SocketClient client(rig.path());
  client.write("throw\nafter\n");
  settle(rig.io);
  CHECK(client.lines() == Lines{"internal: boom", "AFTER"});
}

TEST_CASE("Many clients at once each get their own replies", "[io][control_server]") {
  Rig rig;
  constexpr std::size_t kClients = 40;
  std::vector<std::unique_ptr<SocketClient>> clients;
  for (std::size_t i = 0; i < kClients; ++i) {
    clients.push_back(std::make_unique<SocketClient>(rig.path()));
  }
  settle(rig.io);
  CHECK(rig.server->sessions() == kClients);
  // Half lines of every client first, then the other halves: no client's bytes join another's.
  for (std::size_t i = 0; i < kClients; ++i) {
    clients[i]->write("client" + std::to_string(i));
  }
  settle(rig.io);
  for (std::size_t i = 0; i < kClients; ++i) {
    clients[i]->write("x\nid\n");
  }
  settle(rig.io);
  std::vector<std::string> ids;
  for (std::size_t i = 0; i < kClients; ++i) {
    const Lines lines = clients[i]->lines();
    REQUIRE(lines.size() == 2);
    CHECK(lines[0] == "CLIENT" + std::to_string(i) + "X");
    ids.push_back(lines[1]);
  }
  // Ids are unique, from 1, in the order of connection.
  for (std::size_t i = 0; i < kClients; ++i) {
    CHECK(ids[i] == std::to_string(i + 1));
  }
}

TEST_CASE("A client that disconnects mid-line is forgotten without affecting others",
          "[io][control_server]") {
  std::vector<std::string> handled;
  Rig rig(ControlServer::kDefaultMaxLine, [&](std::string_view line, ControlSession& session) {
    handled.emplace_back(line);
    return answer(line, session);
  });
  SocketClient leaving(rig.path());
  SocketClient staying(rig.path());
  leaving.write("done\nhalf a li");
  staying.write("still ");
  settle(rig.io);
  leaving.close();
  settle(rig.io);
  CHECK(rig.closed == std::vector<std::uint64_t>{1});
  CHECK(rig.server->sessions() == 1);
  staying.write("here\n");
  settle(rig.io);
  CHECK(staying.lines() == Lines{"STILL HERE"});
  CHECK(handled == std::vector<std::string>{"done", "still here"});  // never the half line
}

TEST_CASE("A client that stops sending gets the replies to its complete lines, then the end",
          "[io][control_server]") {
  std::vector<std::string> handled;
  Rig rig(ControlServer::kDefaultMaxLine, [&](std::string_view line, ControlSession& session) {
    handled.emplace_back(line);
    return answer(line, session);
  });
  SocketClient client(rig.path());
  client.write("a\n\n\r\nb\nunfinished");
  client.shutdown_sending();
  settle(rig.io);
  CHECK(client.lines() == Lines{"A", "B"});
  CHECK_FALSE(client.read_now());                        // closed by the server
  CHECK(handled == std::vector<std::string>{"a", "b"});  // empty lines reach no handler
  CHECK(rig.closed == std::vector<std::uint64_t>{1});
}

TEST_CASE("A session sends events after its handler returned, and nothing once it closed",
          "[io][control_server]") {
  ControlSession* subscriber = nullptr;
  Rig rig(ControlServer::kDefaultMaxLine, [&](std::string_view, ControlSession& session) {
    subscriber = &session;
    return std::string("subscribed");
  });
  rig.server->on_close([&](ControlSession& session) {
    CHECK(&session == subscriber);
    subscriber = nullptr;
  });
  SocketClient client(rig.path());
  client.write("subscribe\n");
  settle(rig.io);
  REQUIRE(subscriber != nullptr);
  subscriber->send("event 1");
  subscriber->send("event 2");
  settle(rig.io);
  CHECK(client.lines() == Lines{"subscribed", "event 1", "event 2"});
  client.close();
  settle(rig.io);
  CHECK(subscriber == nullptr);  // on_close ran
}

TEST_CASE("A client that does not read is read no more, then disconnected",
          "[io][control_server]") {
  std::string big(std::size_t{256} * 1024, 'x');
  std::size_t requests = 0;
  Rig rig(ControlServer::kDefaultMaxLine, [&](std::string_view, ControlSession&) {
    ++requests;
    return big;
  });
  SocketClient client(rig.path());
  // Each request queues 256 KiB; above kPauseReadingAbove the server stops reading requests.
  constexpr std::size_t kRequests = 20;
  for (std::size_t i = 0; i < kRequests; ++i) {
    client.write("more\n");
    settle(rig.io);
  }
  const std::size_t paused_at = requests;
  CHECK(paused_at < kRequests);
  CHECK(paused_at >= ControlServer::kPauseReadingAbove / big.size());

  // Reading the replies lets the server read requests again, and every reply comes whole.
  std::size_t received = 0;
  for (int round = 0; round < 100000 && received < kRequests * (big.size() + 1); ++round) {
    received += client.unread();
    client.forget_received();
    settle(rig.io);
  }
  CHECK(requests == kRequests);
  CHECK(received == kRequests * (big.size() + 1));

  // Events keep coming to a client that reads nothing: beyond kMaxQueuedBytes it is let go.
  ControlSession* session = nullptr;
  Rig events(ControlServer::kDefaultMaxLine, [&](std::string_view, ControlSession& s) {
    session = &s;
    return std::string();
  });
  SocketClient idle(events.path());
  idle.write("subscribe\n");
  settle(events.io);
  REQUIRE(session != nullptr);
  const std::string mib(std::size_t{1024} * 1024, 'e');
  for (std::size_t sent = 0; events.closed.empty() && sent < 2 * ControlServer::kMaxQueuedBytes;
       sent += mib.size()) {
    session->send(mib);
    settle(events.io);
  }
  CHECK(events.closed == std::vector<std::uint64_t>{1});
  CHECK(events.server->sessions() == 0);
}

TEST_CASE("The socket file is the owner's, replaces a stale one and goes with the server",
          "[io][control_server]") {
  IoTempDir dir;
  boost::asio::io_context io;
  const fs::path path = dir.path() / "ctl.sock";
  std::vector<std::uint64_t> closed;
  {
    ControlServer server(io, path, answer, replies());
    struct stat st {};
    REQUIRE(::lstat(path.c_str(), &st) == 0);
    CHECK(S_ISSOCK(st.st_mode));
    CHECK((st.st_mode & 0777) == 0600);
    server.on_close([&](ControlSession& session) { closed.push_back(session.id()); });
    // A second server on a live socket is refused, naming the path. Its probe was a connection:
    // session 1, gone at once.
    CHECK_THROWS_WITH(ControlServer(io, path, answer, replies()),
                      Catch::Contains(path.string()) && Catch::Contains("listening"));
    SocketClient client(path);
    settle(io);
    CHECK(closed == std::vector<std::uint64_t>{1});
    CHECK(server.sessions() == 1);
  }
  // The destructor closes the sessions still open, reporting each.
  CHECK(closed == std::vector<std::uint64_t>{1, 2});
  CHECK_FALSE(fs::exists(fs::symlink_status(path)));

  // A socket file nobody listens on (a crashed server's) is replaced.
  {
    const int fd = ::socket(AF_UNIX, SOCK_STREAM, 0);
    sockaddr_un address{};
    address.sun_family = AF_UNIX;
    std::strncpy(static_cast<char*>(address.sun_path), path.c_str(), sizeof address.sun_path - 1);
    // NOLINTNEXTLINE(cppcoreguidelines-pro-type-reinterpret-cast): the sockets API
    REQUIRE(::bind(fd, reinterpret_cast<const sockaddr*>(&address), sizeof address) == 0);
    ::close(fd);
  }
  {
    ControlServer server(io, path, answer, replies());
    SocketClient client(path);
    client.write("hi\n");
    settle(io);
    CHECK(client.lines() == Lines{"HI"});
    // Someone else's file put there meanwhile stays.
    fs::remove(path);
    std::ofstream(path) << "theirs";
  }
  CHECK(fs::is_regular_file(path));
  // Any other file is refused.
  CHECK_THROWS_WITH(ControlServer(io, path, answer, replies()),
                    Catch::Contains(path.string()) && Catch::Contains("not a socket"));
}
