// Who hears a packet: the servos on the line at the client's rate and in the packet's protocol,
// awake, and not silenced by a fault; and the packets nobody can execute (a broken check, a
// malformed instruction), which are answered as real servos answer them.
#include <algorithm>
#include <type_traits>

#include "bus/bus.hpp"
#include "bus/bus_node.hpp"
#include "bus/line_timing.hpp"
#include "wire/instruction_decoder.hpp"
#include "wire/listed_ids.hpp"

namespace dxlemu::bus {

using sim::SimTime;

namespace {

template <class T>
constexpr bool kIsGroupRead =
    std::is_same_v<T, wire::SyncRead> || std::is_same_v<T, wire::FastSyncRead> ||
    std::is_same_v<T, wire::BulkRead> || std::is_same_v<T, wire::FastBulkRead>;

template <class T>
constexpr bool kIsGroupWrite =
    std::is_same_v<T, wire::SyncWrite> || std::is_same_v<T, wire::BulkWrite>;

}  // namespace

Bus::Packet Bus::arrival(wire::Protocol protocol, std::uint8_t id, std::uint8_t instruction,
                         const wire::InstructionPacket* decoded, SimTime end) const {
  Packet packet{{protocol, id, instruction, decoded, end}, {}};
  const bool faulty = this->faulty();
  for (const auto& s : nodes_) {
    if (s->attached && s->servo->protocol() == protocol &&
        baud_matches(client_bps_, s->servo->baud_bps()) && end >= s->booting_until &&
        (!faulty || faults_->available(s->index, end))) {
      packet.listening.push_back({s.get(), {}});
    }
  }
  return packet;
}

std::vector<std::uint8_t> Bus::fault_ids(const Packet& packet) {
  const HeardPacket& heard = packet.heard;
  if (heard.decoded != nullptr && is_group_instruction(heard.protocol, heard.instruction)) {
    return wire::listed_ids(*heard.decoded);
  }
  if (!wire::is_broadcast(heard.protocol, heard.id)) {
    return {heard.id};
  }
  std::vector<std::uint8_t> ids;
  for (const Listener& l : packet.listening) {
    ids.push_back(l.node->servo->id());
  }
  return ids;
}

void Bus::hear(Packet& packet) {
  if (!faulty()) {
    return;
  }
  // The servos a packet is for: its ID (or Secondary ID), the IDs a Sync/Bulk instruction lists
  // (or their Secondary IDs), or every servo listening to a broadcast. The others take no part,
  // and no servo rule applies.
  const HeardPacket& heard = packet.heard;
  const bool broadcast = wire::is_broadcast(heard.protocol, heard.id);
  const std::vector<std::uint8_t> listed =
      heard.decoded != nullptr ? wire::listed_ids(*heard.decoded) : std::vector<std::uint8_t>{};
  std::vector<Listener> hearing;
  hearing.reserve(packet.listening.size());
  auto is_listed = [&listed](std::optional<std::uint8_t> id) {
    return id && std::find(listed.begin(), listed.end(), *id) != listed.end();
  };
  for (Listener& l : packet.listening) {
    const std::uint8_t id = l.node->servo->id();
    const std::optional<std::uint8_t> secondary = l.node->servo->secondary_id();
    // A Sync/Bulk Write block for a Secondary ID is for that group too (Bus::group_write).
    const bool for_it = broadcast ? listed.empty() || is_listed(id) || is_listed(secondary)
                                  : id == heard.id || secondary == heard.id;
    if (for_it) {
      l.hearing = faults_->hear(heard, l.node->index);
    }
    if (l.hearing.hears) {
      hearing.push_back(l);
    }
  }
  packet.listening = std::move(hearing);
}

bool Bus::unicast_reaches(wire::Protocol protocol, std::uint8_t id) {
  // Modbus RTU: a servo whose ID is 0 or over 247 is reached by broadcast alone while it speaks
  // Modbus (docs/modbus.md "Addresses"); 248 ~ 255 are no server's address.
  const wire::ProtocolTraits& t = wire::traits(protocol);
  return id >= t.min_unicast_id && id <= t.max_unicast_id;
}

std::vector<const Bus::Listener*> Bus::addressed(const Packet& packet, std::uint8_t id) {
  std::vector<const Listener*> out;
  if (!unicast_reaches(packet.heard.protocol, id)) {
    return out;
  }
  for (const Listener& l : packet.listening) {
    if (l.node->servo->id() == id) {
      out.push_back(&l);
    }
  }
  return out;
}

void Bus::on_frame(const wire::Frame& frame) {
  const auto decoded = wire::decode_instruction(frame);
  Packet packet = arrival(frame.protocol, frame.id, frame.instruction,
                          std::get_if<wire::InstructionPacket>(&decoded), line_end(frame));
  const SimTime end = packet.heard.end;
  if (faulty()) {
    const InstructionEffects effects = faults_->instruction(packet.heard, fault_ids(packet));
    if (effects.echo) {
      send_at(frame.raw, end, client_bps_, frame.protocol, {}, false);
    }
    if (!effects.noise.empty()) {
      send_at(effects.noise, end, client_bps_, frame.protocol, {}, false);
    }
    if (effects.corrupt) {
      // The servos hear the packet with a broken check and answer as they would.
      packet.heard.decoded = nullptr;
      answer_bad_check(packet, frame.instruction);
      return;
    }
  }
  hear(packet);
  if (const auto* error = std::get_if<wire::DecodeError>(&decoded)) {
    ++stats_.decode_errors;
    // Group instructions are only heard from 0xFE and never answered there; a malformed one is
    // ignored like a well-formed one sent to a single ID.
    if (!wire::is_broadcast(frame.protocol, frame.id) &&
        !is_group_instruction(frame.protocol, frame.instruction)) {
      refuse(packet, *error);
    }
    return;
  }
  std::visit(
      [&](const auto& instruction) {
        using T = std::decay_t<decltype(instruction)>;
        if constexpr (kIsGroupRead<T>) {
          group_read(packet);
        } else if constexpr (kIsGroupWrite<T>) {
          group_write(packet);
        } else {
          single(packet);
        }
      },
      packet.heard.decoded->instruction);
  rearm_watchdogs(packet);
}

void Bus::on_bad_check(const wire::FramingError& error) {
  if (!error.id) {
    return;
  }
  Packet packet = arrival(error.protocol, *error.id, error.instruction.value_or(0), nullptr,
                          error.at + line_time(error.bytes, client_bps_));
  answer_bad_check(packet, error.instruction);
}

void Bus::answer_bad_check(Packet& packet, std::optional<std::uint8_t> instruction) {
  // A servo answers a damaged packet sent to its ID with CRC Error (2.0) or the Checksum Error
  // bit (1.0); the ID is unverified, so whoever has that ID answers. Broadcast: silence.
  if (wire::is_broadcast(packet.heard.protocol, packet.heard.id)) {
    return;
  }
  hear(packet);
  std::vector<Reply> replies;
  for (const Listener* l : addressed(packet, packet.heard.id)) {
    model::ServoResponse r = l->node->servo->bad_check(instruction);
    if (r.replies && l->hearing.answers) {
      replies.push_back(reply_of(packet.heard, *l, std::move(r)));
    }
  }
  answer(packet, {replies}, packet.heard.end);
}

void Bus::refuse(const Packet& packet, const wire::DecodeError& error) {
  std::vector<Reply> replies;
  for (const Listener* l : addressed(packet, packet.heard.id)) {
    model::ServoResponse r = l->node->servo->refuse(error, false);
    if (r.replies && l->hearing.answers) {
      replies.push_back(reply_of(packet.heard, *l, std::move(r)));
    }
  }
  answer(packet, {replies}, packet.heard.end);
}

}  // namespace dxlemu::bus
