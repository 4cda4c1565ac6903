// PtyLink over a real PTY: the test opens the slave side as a client would.
#include "io/pty_link.hpp"

#include <fcntl.h>
#include <termios.h>
#include <unistd.h>

#include <catch2/catch.hpp>

#include <boost/asio/io_context.hpp>
#include <cstdint>
#include <filesystem>
#include <span>
#include <vector>

#include "io_rig.hpp"

namespace {

using dxlemu::io::PtyLink;
using dxlemu::test::IoTempDir;
using dxlemu::test::readable;
using dxlemu::test::run_until;
using dxlemu::test::settle;
namespace fs = std::filesystem;

constexpr std::size_t kPacket = 1000;

// The one place the tests call deliver(): its time and line rate are not used by PtyLink.
constexpr std::uint32_t kAnyBps = 1'000'000;
bool deliver(PtyLink& link, std::span<const std::uint8_t> bytes) {
  return link.deliver(bytes, dxlemu::sim::SimTime{}, kAnyBps);
}

// Packet `n`: kPacket bytes no other packet has at the same place.
std::vector<std::uint8_t> packet(std::size_t n) {
  std::vector<std::uint8_t> bytes(kPacket);
  for (std::size_t i = 0; i < kPacket; ++i) {
    bytes[i] = static_cast<std::uint8_t>(n * 7 + i);
  }
  return bytes;
}

// The client: the slave side, opened by path, raw (PtyLink made it so).
struct PtyClient {
  explicit PtyClient(const std::string& path)
      : fd(::open(path.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC)) {
    REQUIRE(fd >= 0);
  }
  ~PtyClient() { ::close(fd); }
  PtyClient(const PtyClient&) = delete;
  PtyClient& operator=(const PtyClient&) = delete;

  // Reads what is there now (nothing if nothing is).
  std::vector<std::uint8_t> read_now() const {
    std::vector<std::uint8_t> out(65536);
    const ssize_t n = ::read(fd, out.data(), out.size());
    out.resize(n > 0 ? static_cast<std::size_t>(n) : 0);
    return out;
  }

  int fd;
};

}  // namespace

TEST_CASE("The client's bytes reach the callback with the client's baud rate", "[io][pty]") {
  boost::asio::io_context io;
  PtyLink link(io, std::nullopt);
  std::vector<std::uint8_t> got;
  std::uint32_t bps = 0;
  link.start([&](std::span<const std::uint8_t> bytes, std::uint32_t client_bps) {
    got.insert(got.end(), bytes.begin(), bytes.end());
    bps = client_bps;
  });
  PtyClient client(link.slave_path());
  termios t{};
  REQUIRE(tcgetattr(client.fd, &t) == 0);
  cfsetispeed(&t, B1000000);
  cfsetospeed(&t, B1000000);
  REQUIRE(tcsetattr(client.fd, TCSANOW, &t) == 0);

  const std::vector<std::uint8_t> sent = {0xFF, 0xFF, 0xFD, 0x00, 0x01, 0x03, 0x00, 0x01};
  REQUIRE(::write(client.fd, sent.data(), sent.size()) == static_cast<ssize_t>(sent.size()));
  REQUIRE(run_until(io, [&] { return got.size() >= sent.size(); }));
  CHECK(got == sent);
  CHECK(bps == 1000000);
}

TEST_CASE("A packet goes out at once while the client reads", "[io][pty]") {
  boost::asio::io_context io;
  PtyLink link(io, std::nullopt);
  PtyClient client(link.slave_path());
  CHECK(deliver(link, packet(1)));
  CHECK(link.queued_bytes() == 0);
  std::vector<std::uint8_t> got;
  while (got.size() < kPacket && readable(client.fd)) {
    const auto chunk = client.read_now();
    got.insert(got.end(), chunk.begin(), chunk.end());
  }
  CHECK(got == packet(1));
}

TEST_CASE("Packets for a client that does not read wait, up to the limit, then are dropped whole",
          "[io][pty]") {
  boost::asio::io_context io;
  PtyLink link(io, std::nullopt);
  PtyClient client(link.slave_path());

  // Fill the PTY, then the queue. The io_context does not run meanwhile, so nothing of the
  // queue is written: what the queue holds depends only on the deliveries.
  std::vector<std::uint8_t> accepted;
  std::size_t n = 0;
  std::size_t first_queued = 0;
  for (; n < 1000; ++n) {
    const std::size_t before = link.queued_bytes();
    const bool taken = deliver(link, packet(n));
    if (!taken) {
      // Dropped exactly when it would have taken the queue beyond the limit.
      CHECK(before + kPacket > PtyLink::kMaxQueuedBytes);
      CHECK(link.queued_bytes() == before);
      break;
    }
    const auto bytes = packet(n);
    accepted.insert(accepted.end(), bytes.begin(), bytes.end());
    if (first_queued == 0 && link.queued_bytes() > 0) {
      first_queued = n + 1;
    }
    CHECK(link.queued_bytes() <= PtyLink::kMaxQueuedBytes);
  }
  REQUIRE(first_queued > 0);  // the PTY filled
  REQUIRE(n < 1000);          // and then the queue
  // The limit is on bytes: a packet that fits what is left is taken, one byte more is not.
  const std::size_t room = PtyLink::kMaxQueuedBytes - link.queued_bytes();
  CHECK_FALSE(deliver(link, std::vector<std::uint8_t>(room + 1, 0xAA)));
  const std::vector<std::uint8_t> last(room, 0x55);
  CHECK(deliver(link, last));
  accepted.insert(accepted.end(), last.begin(), last.end());
  CHECK(link.queued_bytes() == PtyLink::kMaxQueuedBytes);
  const std::vector<std::uint8_t> small = {1, 2, 3};
  CHECK_FALSE(deliver(link, small));

  // The client reads at last: every accepted packet, whole and in order, none of the dropped.
  std::vector<std::uint8_t> got;
  while (got.size() < accepted.size()) {
    settle(io);
    if (!readable(client.fd)) {
      break;
    }
    const auto chunk = client.read_now();
    got.insert(got.end(), chunk.begin(), chunk.end());
  }
  settle(io);
  CHECK(got.size() == accepted.size());
  CHECK(got == accepted);
  CHECK(link.queued_bytes() == 0);
  CHECK(client.read_now().empty());

  // With the queue empty a packet goes out at once again.
  CHECK(deliver(link, small));
  CHECK(link.queued_bytes() == 0);
  REQUIRE(readable(client.fd));
  CHECK(client.read_now() == small);
}

TEST_CASE("The symlink points at the slave, replaces an old one, and goes with the link",
          "[io][pty]") {
  boost::asio::io_context io;
  IoTempDir dir;
  const fs::path path = dir.path() / "dxl0";
  fs::create_symlink("/dev/null", path);
  {
    PtyLink link(io, path);
    CHECK(link.link() == path);
    CHECK(fs::read_symlink(path) == link.slave_path());
  }
  CHECK_FALSE(fs::exists(fs::symlink_status(path)));

  // Someone else's symlink put there meanwhile stays.
  {
    PtyLink link(io, path);
    fs::remove(path);
    fs::create_symlink("/dev/null", path);
  }
  CHECK(fs::read_symlink(path) == "/dev/null");
}
