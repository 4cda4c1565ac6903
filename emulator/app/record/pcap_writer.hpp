#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <ostream>
#include <span>

#include "sim/sim_time.hpp"
#include "wire/frame.hpp"
#include "wire/protocol.hpp"

namespace dxlemu::app {

/// The link type of dxlemu captures: LINKTYPE_USER0 (DLT 147), which scripts/dxlemu.lua claims.
inline constexpr std::uint32_t kPcapLinkType = 147;
/// The layout version in the first byte of every record's pseudo-header (docs/pcap.md).
inline constexpr std::uint8_t kPcapPseudoHeaderVersion = 1;
/// Bytes of the pseudo-header in front of the line bytes of every record.
inline constexpr std::size_t kPcapPseudoHeaderBytes = 4;
/// Largest number of line bytes kept per record (the global header's snaplen); longer deliveries
/// are cut, with their original length in the record header.
inline constexpr std::uint32_t kPcapSnapLength = 262144;
/// The pseudo-header's port byte for ports past the 255th (config order).
inline constexpr std::uint8_t kPcapPortOverflow = 0xFF;

/// Which way bytes crossed the line: the pseudo-header's second byte.
enum class PcapDirection : std::uint8_t {
  ToServos = 0,  ///< from the client to the servos: instruction packets
  ToClient = 1,  ///< from the servos to the client: status packets
};

/// Writes a classic pcap capture (docs/pcap.md) of what crosses the lines of an emulator to a
/// stream: the global header when constructed, then one record per packet each way, each a 4-byte
/// pseudo-header (version, direction, protocol, port index) and the bytes on the line. The stream
/// is flushed after every record, so a capture is complete whenever the daemon stops and can be
/// read while it runs.
///
/// Timestamps are `start` (wall-clock time of SimTime{}, read by the caller) plus simulated time;
/// this class reads no clock. The stream must outlive the writer. Every framer event carries its
/// own bytes, so the writer keeps nothing between records.
class PcapWriter {
 public:
  /// Writes the global header (magic 0xa1b2c3d4, version 2.4, microseconds, little-endian,
  /// kPcapSnapLength, kPcapLinkType) to `out`. `start` is the wall-clock time, as microseconds
  /// since the Unix epoch, at which simulated time was zero.
  PcapWriter(std::ostream& out, std::chrono::microseconds start);

  /// Writes a client-to-servos record for what port number `port`'s framers heard (config
  /// order): a packet, stamped with its last byte's arrival, or a damaged packet (bad
  /// CRC/checksum, impossible length, truncated) as far as it goes, stamped with its first byte's
  /// arrival. Garbage between packets is not recorded (docs/pcap.md).
  void heard(std::size_t port, const wire::FramerEvent& event);

  /// Writes a servos-to-client record: `bytes` delivered at `at` on port number `port` by servos
  /// speaking `protocol`.
  void sent(std::size_t port, std::span<const std::uint8_t> bytes, sim::SimTime at,
            wire::Protocol protocol);

  /// Writes one record: the pseudo-header (kPcapPseudoHeaderVersion, `direction`, `protocol`
  /// as 1 or 2 or 0 for unknown, `port` or kPcapPortOverflow) and `bytes`, stamped `start` + `at`.
  void write(PcapDirection direction, std::uint8_t protocol, std::size_t port, sim::SimTime at,
             std::span<const std::uint8_t> bytes);

 private:
  std::ostream& out_;
  std::chrono::microseconds start_;
};

}  // namespace dxlemu::app
