#pragma once

#include <boost/asio/io_context.hpp>
#include <boost/asio/posix/stream_descriptor.hpp>
#include <cstdint>
#include <deque>
#include <filesystem>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "bus/byte_link.hpp"

namespace dxlemu::io {

/// One pseudo-terminal: the client opens its slave path as a serial port; dxlemu reads and writes
/// the master. The only code that touches a PTY (DESIGN.md "io/").
///
/// The PTY is raw from creation, and dxlemu keeps its own slave descriptor open for its whole
/// life, so clients may open, close and reopen the port any number of times without the master
/// reporting EIO (and without a busy loop while nobody is connected).
class PtyLink : public bus::ByteLink {
 public:
  /// Bytes that wait for room in the PTY, at most: beyond it, a client that does not read loses
  /// further packets, as a serial adapter's full receive buffer does, instead of the daemon keeping
  /// them without limit and handing them over, stale, whenever the client reads again.
  static constexpr std::size_t kMaxQueuedBytes = std::size_t{64} * 1024;

  /// Called with the bytes the client wrote and the client's baud rate at that moment.
  using OnBytes =
      std::function<void(std::span<const std::uint8_t> bytes, std::uint32_t client_bps)>;

  /// Opens a PTY on `io`. With `link`, also creates a symlink at that path (atomically, replacing
  /// an existing symlink) that is removed when the PtyLink is destroyed. Throws std::system_error.
  PtyLink(boost::asio::io_context& io, std::optional<std::filesystem::path> link);
  ~PtyLink() override;
  PtyLink(const PtyLink&) = delete;
  PtyLink& operator=(const PtyLink&) = delete;

  /// The slave path the client opens, e.g. /dev/pts/5.
  const std::string& slave_path() const { return slave_path_; }
  /// The symlink, if one was asked for.
  const std::optional<std::filesystem::path>& link() const { return link_; }

  /// Starts reading; `on_bytes` is called on the io_context's thread for each chunk.
  void start(OnBytes on_bytes);

  /// Writes `bytes` to the client (queued; never blocks). `at` and `bps` are not used: the driver
  /// calls this at the right moment, and a PTY has no line rate. A packet is never torn: what the
  /// PTY does not take at once waits in a queue, in order, and is written as the client reads.
  /// While the queue is not empty, a packet that would take it beyond kMaxQueuedBytes (the client
  /// reads nothing) is dropped whole: returns false.
  bool deliver(std::span<const std::uint8_t> bytes, sim::SimTime at, std::uint32_t bps) override;
  /// Bytes waiting for room in the PTY now.
  std::size_t queued_bytes() const { return queued_bytes_; }

 private:
  /// Reads the client's bytes and hands them on, again and again.
  void read_more();
  /// Writes as much of `bytes` as the PTY takes now; returns how many it took.
  std::size_t write_now(std::span<const std::uint8_t> bytes);
  /// Writes the front of the queue when the PTY has room, then the rest in order.
  void write_next();

  boost::asio::posix::stream_descriptor master_;
  int slave_fd_ = -1;
  std::string slave_path_;
  std::optional<std::filesystem::path> link_;
  OnBytes on_bytes_;
  std::vector<std::uint8_t> read_buffer_;
  std::deque<std::vector<std::uint8_t>> write_queue_;
  std::size_t queued_bytes_ = 0;  // in write_queue_
};

}  // namespace dxlemu::io
