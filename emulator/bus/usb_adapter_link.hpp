#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include "bus/byte_link.hpp"
#include "sim/scheduler.hpp"

namespace dxlemu::bus {

/// What a USB serial adapter's receive side does to the bytes it hands the host
/// (docs/timing.md "USB adapter latency").
struct UsbAdapter {
  /// The latency timer: how long after its last USB packet the chip sends what it holds; zero
  /// for no adapter (bytes go straight through).
  sim::SimDuration latency{0};
  /// Data bytes in one USB packet (the packet less the chip's 2 modem status bytes).
  std::size_t packet_data = 0;
};

/// Data bytes per USB packet of a full-speed FTDI chip (FT232R): 64 less 2 status bytes.
inline constexpr std::size_t kFullSpeedPacketData = 62;
/// Data bytes per USB packet of a high-speed FTDI chip (FT232H, as in a U2D2): 512 less 2.
inline constexpr std::size_t kHighSpeedPacketData = 510;

/// A ByteLink between the bus and the client that behaves like an FTDI USB serial adapter's
/// receive buffer: it hands bytes on in USB packets, when a packet's worth of data has arrived
/// or when the latency timer expires, whichever comes first. The timer runs from the last USB
/// packet (an idle chip sends an empty status packet every period), so a short reply waits for
/// the next expiry and a reply may be split across two packets. Pure: it takes time from the
/// scheduler and never reads a clock. Takes every byte (deliver() returns true); a packet that
/// the downstream link refuses is counted in unread_drops().
class UsbAdapterLink : public ByteLink {
 public:
  /// An adapter with `adapter`'s timer and packet size (> 0) in front of `downstream`;
  /// `scheduler` and `downstream` must outlive it. Its timer starts at the scheduler's time.
  UsbAdapterLink(sim::Scheduler& scheduler, ByteLink& downstream, UsbAdapter adapter);
  UsbAdapterLink(const UsbAdapterLink&) = delete;
  UsbAdapterLink& operator=(const UsbAdapterLink&) = delete;
  ~UsbAdapterLink() override;

  /// Buffers `bytes`, whose last byte arrived at `at` and the others one byte time apart before
  /// it at `bps`, and sends on the USB packets that fill meanwhile.
  bool deliver(std::span<const std::uint8_t> bytes, sim::SimTime at, std::uint32_t bps) override;

  /// The adapter's settings.
  const UsbAdapter& adapter() const { return adapter_; }
  /// USB packets the downstream link refused (the client was not reading), since it was made.
  std::uint64_t unread_drops() const { return unread_drops_; }

 private:
  /// Lets the timer expire at every period that ends by `t` (the first expiry sends what is
  /// buffered, the others are empty status packets).
  void expire_until(sim::SimTime t);
  /// Hands the buffer on as one USB packet sent at `sent`, which restarts the timer.
  void send(sim::SimTime sent);
  /// Hands the buffer on downstream now, counting a refusal.
  void hand_on();
  /// Arms the timer's event for the next expiry, while bytes wait.
  void arm();

  sim::Scheduler& scheduler_;
  ByteLink& downstream_;
  UsbAdapter adapter_;
  std::uint32_t bps_ = 0;  // the line rate of the latest delivery, which the buffer ends with
  std::vector<std::uint8_t> buffer_;               // received, not yet sent to the host
  sim::SimTime last_packet_;                       // when the chip last sent a USB packet
  sim::SimTime last_byte_;                         // when the latest byte arrived
  std::optional<sim::Scheduler::EventId> expiry_;  // pending while buffer_ holds bytes
  std::uint64_t unread_drops_ = 0;
};

}  // namespace dxlemu::bus
