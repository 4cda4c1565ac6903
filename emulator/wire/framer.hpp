#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "sim/sim_time.hpp"
#include "wire/frame.hpp"
#include "wire/protocol.hpp"

namespace dxlemu::wire {

/// How one protocol lays out a packet, as far as framing needs to know.
struct FrameFormat {
  Protocol protocol = Protocol::V2;
  /// Header bytes (1.0 and FEETECH: FF FF; 2.0: FF FF FD 00, the reserved byte included).
  std::vector<std::uint8_t> header;
  /// Width of the LENGTH field (1.0, FEETECH: 1 byte; 2.0: 2 bytes, little-endian).
  std::size_t length_field_bytes = 2;
  /// Smallest LENGTH value: instruction byte plus the check bytes.
  std::size_t min_length = 3;
  /// Largest LENGTH value accepted; a header announcing more is rejected as impossible, so that
  /// noise cannot make the framer swallow the packets that follow.
  std::size_t max_length = 0;
  /// Width of the integrity check (1.0, FEETECH: checksum, 1 byte; 2.0: CRC-16, 2 bytes).
  std::size_t check_bytes = 2;
  /// A partial packet is dropped when the gap to the next byte exceeds this (protocol1.md and
  /// protocol2.md "Byte to Byte Time": 100 ms and 1.5 ms; FEETECH, undocumented: 1.0's 100 ms).
  sim::SimDuration inter_byte_timeout{};

  /// True for a protocol whose frames end at a silence (Modbus RTU): no header or LENGTH, and
  /// the fields above other than `protocol`, `min_length` and `max_length` (whole frames here)
  /// are unused.
  bool silence_delimited = false;

  /// The format of a protocol's row with the defaults documented in docs/wire.md.
  static FrameFormat for_protocol(Protocol protocol);
};

/// Incremental framer for one protocol. A silence-delimited protocol (Modbus RTU) is framed by
/// the time between bytes instead (see set_line_rate): a frame ends at t3.5 of silence, a gap
/// over t1.5 inside it makes it Truncated, a bad CRC BadCheck, a frame shorter or longer than
/// the protocol allows Truncated or ImpossibleLength.
///
/// Otherwise: an incremental framer Accepts bytes split anywhere, several packets per chunk
/// and garbage around them; yields verified frames and framing errors in arrival order, each with
/// the bytes it covers (`raw`), so that no one outside wire/ needs to find them again.
///
/// After a failed header (invalid ID, impossible length, bad CRC/checksum, timeout) it rescans
/// from the byte after the failed header's first byte, so a packet that starts inside rejected
/// bytes is never lost. Time is an input: the framer never reads a clock.
class Framer {
 public:
  /// A framer with the protocol's default format.
  explicit Framer(Protocol protocol);
  /// A framer with a custom format (e.g. a smaller max_length in tests).
  explicit Framer(FrameFormat format);

  /// Consumes `bytes` that arrived at `at` and appends what they complete to `out`. If the bytes
  /// still buffered are older than the inter-byte timeout, they are resolved first (see expire).
  void feed(std::span<const std::uint8_t> bytes, sim::SimTime at, std::vector<FramerEvent>& out);
  /// As feed(bytes, at, out), with the arrival time of each byte (`times` as long as `bytes`, in
  /// order): for bytes that followed each other on a line.
  void feed(std::span<const std::uint8_t> bytes, std::span<const sim::SimTime> times,
            std::vector<FramerEvent>& out);

  /// Resolves the buffered bytes if the inter-byte timeout has passed at `now`: complete packets
  /// inside them are still yielded, the incomplete rest becomes Truncated or Garbage.
  void expire(sim::SimTime now, std::vector<FramerEvent>& out);

  /// The earliest time at which expire() would drop the buffered partial packet (or end a
  /// silence-delimited frame); nullopt when nothing is buffered.
  std::optional<sim::SimTime> deadline() const;

  /// The client's bit rate from now on: a silence-delimited framer measures character times at
  /// it (a byte lasts 10 bits on the line; the silences follow the protocol's row). Other
  /// framers ignore it.
  void set_line_rate(std::uint32_t bps) { bps_ = bps; }

  /// The client's write has ended and the line is taken to be silent after it (timing without
  /// modelled delays, where simulated time may not move): a silence-delimited frame ends here.
  /// Other framers ignore it.
  void end_of_write(std::vector<FramerEvent>& out);

  /// Bytes fed so far, in all: the offset the next byte fed will have.
  std::uint64_t fed() const { return dropped_ + buf_.size() + overflow_; }

  /// Bytes held while waiting for the rest of a packet.
  std::size_t buffered() const { return buf_.size() - start_; }

  /// The layout this framer parses.
  const FrameFormat& format() const { return format_; }

 private:
  void scan(bool stale, std::vector<FramerEvent>& out);
  std::size_t find_header(std::size_t from) const;
  bool check_ok(std::size_t pos, std::size_t total) const;
  Frame make_frame(std::size_t pos, std::size_t total) const;
  void skip_garbage(std::size_t count);
  void reject(FramingErrorKind kind, std::size_t pos, std::size_t bytes,
              std::vector<FramerEvent>& out);
  void flush_garbage(std::vector<FramerEvent>& out);
  void compact();
  // Silence-delimited framing (framer_silence.cpp).
  void feed_silent(std::span<const std::uint8_t> bytes, std::span<const sim::SimTime> times,
                   std::vector<FramerEvent>& out);
  void close_silent(std::vector<FramerEvent>& out);
  sim::SimDuration byte_time() const;

  FrameFormat format_;
  std::vector<std::uint8_t> buf_;
  std::vector<sim::SimTime> times_;  // arrival time of each byte in buf_
  std::size_t start_ = 0;            // first byte not yet resolved
  std::size_t quiet_end_ = 0;        // bytes before this were already reported by an error
  sim::SimTime last_at_{};
  std::size_t garbage_count_ = 0;  // garbage run not yet reported
  sim::SimTime garbage_at_{};
  std::uint64_t garbage_offset_ = 0;
  std::uint64_t dropped_ = 0;  // bytes removed from the front of buf_ so far
  // Silence-delimited framing: the client's rate, when the last byte ended, whether a gap over
  // t1.5 broke the frame, and the bytes of an overlong frame not kept.
  std::uint32_t bps_ = 0;
  sim::SimTime last_end_{};
  bool broken_ = false;
  std::uint64_t overflow_ = 0;
};

}  // namespace dxlemu::wire
