// The receive side of an FTDI USB serial adapter (FTDI AN232B-04 "Data Throughput, Latency and
// Handshaking", docs/timing.md "USB adapter latency"): the chip sends the host a USB packet when
// its buffer holds a packet's worth of data, or when its latency timer, which counts from the
// last packet it sent, expires; an expiry with nothing buffered sends the 2 status bytes alone
// and restarts the timer all the same.
#include "bus/usb_adapter_link.hpp"

#include <algorithm>
#include <cassert>

#include "bus/line_timing.hpp"

namespace dxlemu::bus {

using sim::SimTime;

UsbAdapterLink::UsbAdapterLink(sim::Scheduler& scheduler, ByteLink& downstream, UsbAdapter adapter)
    : scheduler_(scheduler),
      downstream_(downstream),
      adapter_(adapter),
      last_packet_(scheduler.now()),
      last_byte_(scheduler.now()) {
  assert(adapter_.latency >= sim::SimDuration::zero() && adapter_.packet_data > 0);
}

UsbAdapterLink::~UsbAdapterLink() {
  if (expiry_) {
    scheduler_.cancel(*expiry_);
  }
}

bool UsbAdapterLink::deliver(std::span<const std::uint8_t> bytes, SimTime at, std::uint32_t bps) {
  bps_ = bps;
  if (adapter_.latency == sim::SimDuration::zero()) {
    return downstream_.deliver(bytes, at, bps_);
  }
  const std::size_t n = bytes.size();
  for (std::size_t i = 0; i < n; ++i) {
    // A byte has arrived when its stop bit has: the bytes after it still take their wire time.
    const SimTime arrived = std::max(at - wire_time(n - 1 - i, bps_), last_byte_);
    last_byte_ = arrived;
    if (arrived < last_packet_) {
      // It was on the line while a packet the timer sent left, and belongs to that packet; the
      // bus hands a status over only once it is complete, so it goes now, late by less than
      // the status's wire time, and the timer keeps counting from that packet.
      buffer_.push_back(bytes[i]);
      if (i + 1 == n || at - wire_time(n - 2 - i, bps_) >= last_packet_) {
        hand_on();
      }
      continue;
    }
    expire_until(arrived);
    buffer_.push_back(bytes[i]);
    if (buffer_.size() == adapter_.packet_data) {
      send(arrived);
    }
  }
  arm();
  return true;
}

void UsbAdapterLink::expire_until(SimTime t) {
  // The timer expires at last_packet_ + k x latency (k >= 1) until a packet restarts it; an
  // expiry at t comes before a byte arriving at t, which waits for the next one.
  const SimTime first = last_packet_ + adapter_.latency;
  if (t < first) {
    return;
  }
  const SimTime last = last_packet_ + ((t - last_packet_) / adapter_.latency) * adapter_.latency;
  if (!buffer_.empty()) {
    send(first);
  }
  last_packet_ = last;  // the later expiries were empty status packets
}

void UsbAdapterLink::send(SimTime sent) {
  last_packet_ = sent;
  hand_on();
}

void UsbAdapterLink::hand_on() {
  // A packet due while a status was still on the line goes when the bus hands it over (now).
  if (!downstream_.deliver(buffer_, scheduler_.now(), bps_)) {
    ++unread_drops_;
  }
  buffer_.clear();
}

void UsbAdapterLink::arm() {
  if (expiry_) {
    scheduler_.cancel(*expiry_);
    expiry_.reset();
  }
  if (buffer_.empty()) {
    return;
  }
  expiry_ = scheduler_.schedule_at(last_packet_ + adapter_.latency, [this] {
    expiry_.reset();
    expire_until(scheduler_.now());
  });
}

}  // namespace dxlemu::bus
