// When replies reach the client: instruction wire time, processing, Return Delay Time and status
// wire time on the virtual clock (DESIGN.md "Time"), chained group after group; and what applies
// once a status is out (deferred identity changes, reboots).
#include <algorithm>

#include "bus/bus.hpp"
#include "bus/bus_node.hpp"
#include "bus/collision.hpp"
#include "bus/line_timing.hpp"
#include "wire/packet_encoder.hpp"
#include "wire/rtu_timing.hpp"

namespace dxlemu::bus {

using sim::SimDuration;
using sim::SimTime;

SimDuration Bus::line_time(std::size_t bytes, std::uint32_t bps) const {
  return timing_ == ReplyTiming::Modelled ? wire_time(bytes, bps) : SimDuration{0};
}

// "For an instruction whose bytes arrived at t: line_end = t + wire(instruction)" (DESIGN.md).
// A packet written in pieces cannot end before its last piece arrived plus one byte time. The
// bytes of one write are stamped back to back (receive), so they take the first branch.
SimTime Bus::line_end(const wire::Frame& frame) const {
  const std::size_t size = frame.raw.size();
  // A frame that ends at a silence (Modbus RTU) is only known to have ended once the silence
  // has passed: the device starts processing t3.5 after the last byte.
  const wire::FrameShape& shape = wire::traits(frame.protocol).frame;
  const SimDuration silence =
      timing_ == ReplyTiming::Modelled && shape.delimiting == wire::Delimiting::Silence
          ? wire::frame_silence(shape, client_bps_)
          : SimDuration{0};
  if (frame.last_byte_at <= frame.first_byte_at + line_time(size - 1, client_bps_)) {
    return frame.first_byte_at + line_time(size, client_bps_) + silence;
  }
  return frame.last_byte_at + line_time(1, client_bps_) + silence;
}

SimDuration Bus::turnaround(const Reply& reply) const {
  if (timing_ == ReplyTiming::Immediate) {
    return reply.extra_delay;  // an injected delay shows in every timing mode
  }
  return reply.response.processing + reply.node->servo->return_delay() + reply.extra_delay;
}

Bus::Reply Bus::reply_of(const HeardPacket& heard, const Listener& listener,
                         model::ServoResponse response) const {
  std::vector<std::uint8_t> bytes = status_bytes(heard, *listener.node, response);
  return {listener.node, std::move(response), std::move(bytes), listener.hearing.extra_delay};
}

wire::Protocol Bus::status_protocol(const Node& node) {
  return node.servo->protocol().value_or(wire::kDefaultProtocol);
}

std::vector<std::uint8_t> Bus::status_bytes(const HeardPacket& heard, const Node& node,
                                            const model::ServoResponse& response) const {
  // Modbus RTU answers with the request's function code and echoes parts of it.
  const wire::Answering answering{heard.instruction,
                                  heard.decoded != nullptr ? &heard.decoded->instruction : nullptr};
  return wire::encode_reply(
      {status_protocol(node), node.servo->id(), response.error, response.params}, answering);
}

void Bus::answer(const Packet& packet, const std::vector<ReplyGroup>& groups, SimTime start_after) {
  // A reply starts after the instruction (or the previous group) ends, plus the servo's own
  // processing time and Return Delay Time, and reaches the client when its last byte would.
  SimTime after = start_after;
  for (const ReplyGroup& group : groups) {
    if (group.empty()) {
      continue;
    }
    SimTime group_end = after;
    std::vector<std::vector<std::uint8_t>> packets;
    std::vector<Settlement> settlements;
    for (const Reply& r : group) {
      std::vector<std::uint8_t> bytes = r.bytes;
      ReplyEffects effects;
      if (faulty()) {
        effects = faults_->reply(packet.heard, {r.node->servo->id()}, bytes,
                                 status_protocol(*r.node), scheduler_.now());
      }
      const SimTime start = after + turnaround(r) + effects.delay;
      // A dropped status still took its time on the line: the chain after it keeps its timing.
      const std::size_t on_line = effects.dropped ? r.bytes.size() : bytes.size();
      group_end = std::max(group_end, start + line_time(on_line, r.node->servo->baud_bps()));
      if (!bytes.empty()) {
        packets.push_back(std::move(bytes));
      }
      settlements.push_back({r.node, r.response.reboot_after});
    }
    if (group.size() > 1) {
      ++stats_.id_conflicts;
    }
    send_at(collide(packets), group_end, group.front().node->servo->baud_bps(),
            status_protocol(*group.front().node), std::move(settlements));
    after = group_end;
  }
}

void Bus::send_at(std::vector<std::uint8_t> bytes, SimTime at, std::uint32_t bps,
                  wire::Protocol protocol, std::vector<Settlement> settlements, bool is_reply) {
  auto outgoing = std::make_shared<Outgoing>();
  outgoing_.push_back(outgoing);
  // The rate the bytes took on the line, as line_time() counted it.
  const std::uint32_t rate = timing_ == ReplyTiming::Modelled ? bps : 0;
  scheduler_.schedule_at(at, [this, at, outgoing, protocol, is_reply, rate,
                              bytes = std::move(bytes), settlements = std::move(settlements)] {
    std::erase(outgoing_, outgoing);
    if (!outgoing->cancelled && !bytes.empty()) {
      // The modelled time, not now(): when it had passed before the event could run (bytes read
      // late off a busy machine), the link sees by how much. Never before the previous
      // delivery's: the line carries them in order.
      last_sent_ = std::max(at, last_sent_);
      if (link_.deliver(bytes, last_sent_, rate)) {
        stats_.replies += is_reply ? 1 : 0;
      } else {
        ++stats_.unread_drops;
      }
      if (observer_.sent) {
        observer_.sent(bytes, last_sent_, protocol);
      }
    }
    // ID, Baud Rate, Protocol Type and Return Delay Time change after the status went out.
    for (const Settlement& s : settlements) {
      settle(*s.node, s.reboot, scheduler_.now());
    }
  });
}

void Bus::settle(Node& node, bool reboot, SimTime at) {
  node.servo->advance_to(at);
  node.servo->commit_deferred();
  if (reboot) {
    restart(node, at);
  }
}

void Bus::restart(Node& node, SimTime at) {
  node.servo->reboot();
  if (faults_ != nullptr) {
    faults_->rebooted(node.index);
  }
  node.booting_until = at + node.servo->boot_time();
}

}  // namespace dxlemu::bus
