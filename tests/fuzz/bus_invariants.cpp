#include "bus_invariants.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <type_traits>
#include <utility>
#include <variant>

#include "fuzz_require.hpp"
#include "wire/crc16.hpp"
#include "wire/framer.hpp"
#include "wire/instruction_decoder.hpp"
#include "wire/status_error.hpp"

namespace dxlemu::fuzz {

namespace {

// Fast Sync/Bulk Read reply layout (protocol2.md "Fast Sync Read (0x8A)"): FF FF FD 00 FE LEN_L
// LEN_H 0x55, then per device [error, ID, data, CRC_L, CRC_H], each CRC the running CRC of the
// packet so far (the last one the packet's own).
constexpr std::array<std::uint8_t, 5> kFastReplyHead = {0xFF, 0xFF, 0xFD, 0x00, 0xFE};
constexpr std::size_t kFastReplyBlocksAt = 8;
constexpr std::size_t kFastBlockOverhead = 4;  // error, ID, CRC
constexpr std::size_t kPacketHeadBytes = 7;    // what LENGTH does not count: header, ID, LENGTH
constexpr std::uint8_t kMaxV2ErrorNumber = 0x07;
constexpr std::uint8_t kV1UnusedErrorBit = 0x80;
// Operating Mode values whose Goal Position spans many turns (X, MX(2.0), P).
constexpr std::int64_t kExtendedPositionMode = 4;
constexpr std::int64_t kCurrentBasedPositionMode = 5;

// The devices a Fast read lists and the bytes each must send, or nothing for any other packet.
// Sync and Bulk reads answer an ID's first listing only (protocol1.md "Bulk Read"; docs/bus.md).
template <class Layout>
std::optional<Layout> fast_read_layout(const wire::Frame& frame) {
  const auto decoded = wire::decode_instruction(frame);
  const auto* packet = std::get_if<wire::InstructionPacket>(&decoded);
  if (packet == nullptr || packet->id != wire::kBroadcastId) {
    return std::nullopt;
  }
  Layout layout;
  auto add = [&](std::uint8_t id, std::uint16_t length) {
    if (std::none_of(layout.begin(), layout.end(), [&](const auto& b) { return b.id == id; })) {
      layout.push_back({id, length});
    }
  };
  if (const auto* sync = std::get_if<wire::FastSyncRead>(&packet->instruction)) {
    for (const std::uint8_t id : sync->ids) {
      add(id, sync->length);
    }
    return layout;
  }
  if (const auto* bulk = std::get_if<wire::FastBulkRead>(&packet->instruction)) {
    for (const wire::BulkReadTarget& t : bulk->targets) {
      add(t.id, t.length);
    }
    return layout;
  }
  return std::nullopt;
}

bool valid_error_byte(std::uint8_t error, wire::Protocol protocol) {
  if (protocol == wire::Protocol::V1) {
    return (error & kV1UnusedErrorBit) == 0;
  }
  return (error & static_cast<std::uint8_t>(~wire::kAlertBit)) <= kMaxV2ErrorNumber;
}

}  // namespace

bool item_value_allowed(const model::Servo& servo, std::size_t item, std::int64_t value) {
  const model::ModelSpec& spec = servo.spec();
  const model::ItemSpec& item_spec = spec.items[item];
  if (item_spec.in_range(value)) {
    return true;
  }
  // The device marks an expired Bus Watchdog with -1, outside what a write may set
  // (includes/control_table_buswatchdog.md; docs/bus.md "Bus Watchdog").
  if (item_spec.key == "bus_watchdog") {
    return value == -1;
  }
  // Extended and Current-based Position Control Mode take goals over many turns instead of
  // the position range (includes/control_table_opmode_six_2.md; MotionModel's range rule).
  const auto mode = spec.index_of("operating_mode");
  const bool multi_turn_family = spec.traits().extended_goals != model::ExtendedGoals::ItemRange;
  if (item_spec.key == "goal_position" && mode && multi_turn_family) {
    const std::int64_t m = servo.table().get(*mode);
    return m == kExtendedPositionMode || m == kCurrentBasedPositionMode;
  }
  return false;
}

// The range check is left out of the coverage instrumentation (fuzz_require.hpp): its loops tell
// the fuzzer nothing about dxlemu.
FUZZ_NO_COVERAGE void RangeChecker::check() {
  for (std::size_t s = 0; s < seen_.size(); ++s) {
    check_servo(*bus_.servos().at(s), seen_[s]);
  }
}

FUZZ_NO_COVERAGE void RangeChecker::check_servo(const model::Servo& servo,
                                                std::vector<std::uint8_t>& seen) {
  // Raw pointers, not operator[]: the containers' operators are instrumented code, and calls
  // to them here were a tenth of the target's time.
  const std::span<const std::uint8_t> bytes = servo.table().bytes();
  const std::uint8_t* now = bytes.data();
  const std::uint8_t* before = seen.data();
  const std::vector<model::ItemSpec>& items = servo.spec().items;
  const model::ItemSpec* item = items.data();
  const bool first = seen.empty();
  for (std::size_t i = 0; i < items.size(); ++i) {
    bool differs = first;
    for (std::size_t at = item[i].address; !differs && at < item[i].end(); ++at) {
      differs = now[at] != before[at];
    }
    if (differs) {
      const std::int64_t value = servo.table().get(i);
      FUZZ_REQUIRE_MSG(item_value_allowed(servo, i, value), "%s ID %u: %s = %lld",
                       servo.spec().name.c_str(), unsigned{servo.id()}, item[i].key.c_str(),
                       static_cast<long long>(value));
    }
  }
  seen.assign(bytes.begin(), bytes.end());
}

ReplyChecker::ReplyChecker(bus::Bus& bus, const bus::LoopbackLink& link,
                           std::function<void()> before_packet)
    : bus_(bus), link_(link), before_packet_(std::move(before_packet)) {
  bus.set_observer({[this](const wire::FramerEvent& event) { heard(event); },
                    [this](std::span<const std::uint8_t> bytes, sim::SimTime at,
                           wire::Protocol protocol) { sent(bytes, at, protocol); }});
  remember_servos();
}

void ReplyChecker::remember_servos() {
  for (const auto& servo : bus_.servos()) {
    ids_.insert(servo->id());
    if (const auto protocol = servo->protocol()) {
      protocols_.insert(*protocol);
    }
  }
}

void ReplyChecker::heard(const wire::FramerEvent& event) {
  if (before_packet_) {
    before_packet_();
  }
  // Heard events come from Bus::handle, after receive() dropped any replies still due (counted
  // as a collision): what was expected of them is void.
  if (bus_.stats().collisions != collisions_seen_) {
    collisions_seen_ = bus_.stats().collisions;
    conflicts_base_ = bus_.stats().id_conflicts;
    excused_ = 0;
    ids_.clear();
    protocols_.clear();
    fast_requests_.clear();
  }
  // Replies to this packet carry the IDs and protocols the servos have while it is handled.
  remember_servos();
  // A frame or a bad-check packet cancels whatever was still due (Bus::handle): on a FEETECH bus,
  // what may come now answers it.
  const auto* failure = std::get_if<wire::FramingError>(&event);
  const wire::Protocol protocol =
      failure != nullptr ? failure->protocol : std::get<wire::Frame>(event).protocol;
  const bool cancels = failure == nullptr || failure->kind == wire::FramingErrorKind::BadCheck;
  if (protocol == wire::Protocol::Feetech && cancels) {
    feetech_.heard(event, bus_);
  }
  if (cancels) {
    modbus_.heard(event, bus_);
  }
  if (const auto* frame = std::get_if<wire::Frame>(&event)) {
    if (auto layout = fast_read_layout<Layout>(*frame); layout && !layout->empty()) {
      fast_requests_.push_back(std::move(*layout));
    }
  }
}

void ReplyChecker::sent(std::span<const std::uint8_t> bytes, sim::SimTime at,
                        wire::Protocol protocol) {
  FUZZ_REQUIRE(!bytes.empty());
  // The observer and the link see the same deliveries, in time order.
  FUZZ_REQUIRE(link_.deliveries().size() == checked_ + 1);
  const bus::LoopbackLink::Delivery& delivery = link_.deliveries().back();
  FUZZ_REQUIRE(
      std::equal(bytes.begin(), bytes.end(), delivery.bytes.begin(), delivery.bytes.end()));
  FUZZ_REQUIRE(delivery.at == at);
  FUZZ_REQUIRE(at >= last_delivery_);
  last_delivery_ = at;
  ++checked_;

  FUZZ_REQUIRE(protocols_.contains(protocol));
  const bool conflict_pending = bus_.stats().id_conflicts - conflicts_base_ > excused_;
  if (protocol == wire::Protocol::Feetech) {
    excused_ += feetech_.check(bytes, at, conflict_pending) ? 1 : 0;
    return;
  }
  if (protocol == wire::Protocol::Modbus) {
    excused_ += modbus_.check(bytes, at, conflict_pending) ? 1 : 0;
    return;
  }
  if (protocol == wire::Protocol::V2 && is_fast_reply(bytes)) {
    return;
  }
  if (is_status(bytes, protocol)) {
    return;
  }
  // Only servos sharing an ID (or 1.0 servos answering one broadcast Ping) send at once, and the
  // bus counts each such slot: without one pending, the delivery is simply malformed.
  FUZZ_REQUIRE_MSG(conflict_pending,
                   "malformed delivery of %zu bytes (protocol %d) with no ID conflict pending",
                   bytes.size(), protocol == wire::Protocol::V1 ? 1 : 2);
  ++excused_;
  // The AND of packets that all start with the header is a packet starting with it.
  const wire::FrameFormat format = wire::FrameFormat::for_protocol(protocol);
  FUZZ_REQUIRE(bytes.size() >= format.header.size());
  FUZZ_REQUIRE(std::equal(format.header.begin(), format.header.end(), bytes.begin()));
}

// Exactly one status packet of `protocol`, nothing before or after it.
bool ReplyChecker::is_status(std::span<const std::uint8_t> bytes, wire::Protocol protocol) const {
  wire::Framer framer(protocol);
  std::vector<wire::FramerEvent> events;
  framer.feed(bytes, sim::SimTime{}, events);
  framer.expire(sim::SimTime{} + std::chrono::hours(1), events);
  if (events.size() != 1 || !std::holds_alternative<wire::Frame>(events.front())) {
    return false;
  }
  const auto& frame = std::get<wire::Frame>(events.front());
  if (!std::equal(bytes.begin(), bytes.end(), frame.raw.begin(), frame.raw.end())) {
    return false;
  }
  const auto decoded = wire::decode_status(frame);
  const auto* status = std::get_if<wire::StatusPacket>(&decoded);
  return status != nullptr && status->id <= wire::max_unicast_id(protocol) &&
         ids_.contains(status->id) && valid_error_byte(status->error, protocol);
}

// The reply to one of the Fast reads heard, whole or cut short after the last device that
// answered (docs/bus.md "Group instructions"); a match is used up.
bool ReplyChecker::is_fast_reply(std::span<const std::uint8_t> bytes) {
  if (bytes.size() < kFastReplyBlocksAt ||
      !std::equal(kFastReplyHead.begin(), kFastReplyHead.end(), bytes.begin()) ||
      bytes[kFastReplyBlocksAt - 1] != wire::to_byte(wire::InstructionCode::Status)) {
    return false;
  }
  const std::size_t length = bytes[5] | (static_cast<std::size_t>(bytes[6]) << 8);
  auto matches = [&](const Layout& layout) {
    std::size_t full = kFastReplyBlocksAt;
    for (const Block& b : layout) {
      full += kFastBlockOverhead + b.length;
    }
    if (length + kPacketHeadBytes != full) {
      return false;
    }
    std::size_t at = kFastReplyBlocksAt;
    std::size_t blocks = 0;
    for (const Block& b : layout) {
      if (at == bytes.size()) {
        break;
      }
      const std::size_t crc_at = at + 2 + b.length;
      if (crc_at + 2 > bytes.size() || bytes[at + 1] != b.id ||
          !valid_error_byte(bytes[at], wire::Protocol::V2)) {
        return false;
      }
      // A device whose read failed sends zeros, so that the layout stays parseable.
      const auto data = bytes.subspan(at + 2, b.length);
      if ((bytes[at] & static_cast<std::uint8_t>(~wire::kAlertBit)) != 0 &&
          std::any_of(data.begin(), data.end(), [](std::uint8_t x) { return x != 0; })) {
        return false;
      }
      const std::uint16_t crc = wire::crc16(bytes.first(crc_at));
      if (bytes[crc_at] != (crc & 0xFFU) || bytes[crc_at + 1] != (crc >> 8)) {
        return false;
      }
      at = crc_at + 2;
      ++blocks;
    }
    return blocks > 0 && at == bytes.size();
  };
  const auto it = std::find_if(fast_requests_.begin(), fast_requests_.end(), matches);
  if (it == fast_requests_.end()) {
    return false;
  }
  fast_requests_.erase(it);
  return true;
}

void ReplyChecker::finish() const {
  FUZZ_REQUIRE(link_.deliveries().size() == checked_);
}

}  // namespace dxlemu::fuzz
