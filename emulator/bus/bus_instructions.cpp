// What the addressed servos do with an instruction: a single-target instruction (or a broadcast
// one), and the Sync/Bulk instructions that list their devices, with the chained and the Fast
// replies they ask for (protocol1.md, protocol2.md; rules in docs/bus.md).
#include <algorithm>

#include "bus/bus.hpp"
#include "bus/bus_node.hpp"
#include "bus/collision.hpp"
#include "wire/listed_ids.hpp"
#include "wire/packet_encoder.hpp"

namespace dxlemu::bus {

using sim::SimTime;

void Bus::single(const Packet& packet) {
  const wire::InstructionPacket& instruction = *packet.heard.decoded;
  const SimTime end = packet.heard.end;
  const bool broadcast = wire::is_broadcast(instruction.protocol, instruction.id);
  const bool reachable = unicast_reaches(instruction.protocol, instruction.id);
  std::vector<std::pair<const Listener*, model::Addressing>> targets;
  for (const Listener& l : packet.listening) {
    const model::Servo& servo = *l.node->servo;
    if (broadcast) {
      targets.emplace_back(&l, model::Addressing::Broadcast);
    } else if (servo.id() == instruction.id && reachable) {
      targets.emplace_back(&l, model::Addressing::Unicast);
    } else if (servo.secondary_id() == instruction.id) {
      // The ID takes priority, but the group of that Secondary ID executes too, silently.
      targets.emplace_back(&l, model::Addressing::Secondary);
    }
  }
  // Broadcast Ping: every servo answers, in ascending ID order (protocol2.md "Ping" Example 2).
  std::stable_sort(targets.begin(), targets.end(), [](const auto& a, const auto& b) {
    return a.first->node->servo->id() < b.first->node->servo->id();
  });
  std::vector<Reply> replies;
  const auto* write = std::get_if<wire::Write>(&instruction.instruction);
  for (const auto& [l, addressing] : targets) {
    Node& s = *l->node;
    // A fault may make the servo refuse the packet unexecuted, with a code of its choosing
    // (modbus_exception): answered as a refusal is, after a refusal's processing time.
    const bool refused = l->hearing.refusal != 0;
    model::ServoResponse r =
        refused ? s.servo->refuse({wire::DecodeErrorKind::BadValue, instruction.id,
                                   packet.heard.instruction, "refused by a fault rule"},
                                  broadcast)
                : s.servo->execute(instruction, addressing);
    if (refused) {
      r.error = l->hearing.refusal;
    }
    if (write != nullptr && !refused && faulty()) {
      faults_->wrote(packet.heard, s.index, write->address, write->data);
    }
    if (r.replies && l->hearing.answers) {
      replies.push_back(reply_of(packet.heard, *l, std::move(r)));
    } else {
      settle(s, r.reboot_after, end);
    }
  }
  // Protocol 2.0 chains broadcast Ping replies, one group per ID (servos sharing an ID collide in
  // theirs); Protocol 1.0 defines no order, so 1.0 servos answer a broadcast Ping at once and
  // collide when there are several. A unicast instruction has one group (docs/bus.md).
  std::vector<ReplyGroup> groups;
  for (Reply& r : replies) {
    const bool new_group =
        groups.empty() || (broadcast && wire::traits(instruction.protocol).chained_broadcast_ping &&
                           groups.back().front().node->servo->id() != r.node->servo->id());
    if (new_group) {
      groups.emplace_back();
    }
    groups.back().push_back(std::move(r));
  }
  answer(packet, groups, end);
}

void Bus::group_read(const Packet& packet) {
  if (!wire::is_broadcast(packet.heard.protocol, packet.heard.id)) {
    return;  // "The Packet ID must be 0xFE": a servo ignores a Sync/Bulk Read sent to its own ID
  }
  const ReadRequest request = read_request(*packet.heard.decoded);
  // A Fast reply announces every listed device's block in one 16-bit LENGTH: a request for more
  // than that can announce has no reply any device could send, so it goes unanswered.
  if (request.fast) {
    std::vector<std::size_t> sizes;
    for (const ReadPart& part : request.parts) {
      sizes.push_back(part.length);
    }
    if (!wire::fast_reply_length(sizes)) {
      return;
    }
  }
  std::vector<ReplyGroup> answered;  // one per listed device that answers, in list order
  for (const ReadPart& part : request.parts) {
    std::vector<const Listener*> matches = addressed(packet, part.id);
    std::erase_if(matches, [&](const Listener* l) {
      const model::Servo& servo = *l->node->servo;
      return !servo.replies_to(true) || (request.fast && !servo.supports_fast_read()) ||
             (request.v1_bulk && !servo.supports_v1_bulk_read());
    });
    ReplyGroup out;
    for (const Listener* l : matches) {  // servos sharing the ID all answer, and collide
      model::ServoResponse r = l->node->servo->read_part(part.address, part.length);
      if (!r.replies) {
        continue;  // a refusal it answers with silence (FEETECH: a read outside the table)
      }
      if (request.fast) {
        r.params.resize(part.length, 0);  // a failed read still fills its block (docs/bus.md)
        out.push_back({l->node, std::move(r), {}, l->hearing.extra_delay});
      } else {
        out.push_back(reply_of(packet.heard, *l, std::move(r)));
      }
    }
    // Each device waits for the status of the one before it (protocol1.md "Bulk Read"): when a
    // listed device does not answer, the ones after it wait in vain and stay silent.
    if (out.empty()) {
      break;
    }
    answered.push_back(std::move(out));
  }
  if (answered.empty()) {
    return;
  }
  if (request.fast) {
    fast_read(packet, request.parts, answered);
  } else {
    answer(packet, answered, packet.heard.end);
  }
}

void Bus::fast_read(const Packet& packet, const std::vector<ReadPart>& parts,
                    const std::vector<ReplyGroup>& answered) {
  // Fast Sync/Bulk Read: one packet from ID 0xFE, charged one processing time and one Return
  // Delay Time (the first device's). If the chain broke, LENGTH still announces every listed
  // device and the packet stops after the last block sent: the client sees it cut short. Where
  // servos share an ID, each sends its own version of the packet at once: they collide.
  std::size_t versions = 0;
  for (const ReplyGroup& group : answered) {
    versions = std::max(versions, group.size());
    stats_.id_conflicts += group.size() > 1 ? 1 : 0;
  }
  std::vector<std::vector<std::uint8_t>> packets;
  for (std::size_t v = 0; v < versions; ++v) {
    wire::FastReply reply;
    for (std::size_t i = 0; i < parts.size(); ++i) {
      if (i < answered.size()) {
        const Reply& r = answered[i][std::min(v, answered[i].size() - 1)];
        reply.blocks.push_back({r.response.error, parts[i].id, r.response.params});
      } else {
        reply.blocks.push_back({0, parts[i].id, std::vector<std::uint8_t>(parts[i].length, 0)});
      }
    }
    packets.push_back(wire::encode_fast_reply(reply, answered.size()));
  }
  const Reply& first = answered.front().front();
  std::vector<Settlement> settlements;
  std::vector<std::uint8_t> ids;
  for (const ReplyGroup& group : answered) {
    for (const Reply& r : group) {
      settlements.push_back({r.node, false});
      ids.push_back(r.node->servo->id());
    }
  }
  std::vector<std::uint8_t> bytes = collide(packets);
  const std::size_t sent_size = bytes.size();
  const wire::Protocol protocol = packet.heard.protocol;  // only 2.0 has Fast replies
  ReplyEffects effects;
  if (faulty()) {
    effects = faults_->reply(packet.heard, std::move(ids), bytes, protocol, scheduler_.now());
  }
  const SimTime start = packet.heard.end + turnaround(first) + effects.delay;
  const std::uint32_t bps = first.node->servo->baud_bps();
  const SimTime delivered = start + line_time(effects.dropped ? sent_size : bytes.size(), bps);
  send_at(std::move(bytes), delivered, bps, protocol, std::move(settlements));
}

void Bus::group_write(const Packet& packet) {
  if (!wire::is_broadcast(packet.heard.protocol, packet.heard.id)) {
    return;  // "The Packet ID must be 0xFE"
  }
  const std::vector<std::uint8_t> listed = wire::listed_ids(*packet.heard.decoded);
  auto write_to = [&](std::uint8_t id, std::uint16_t address,
                      const std::vector<std::uint8_t>& data) {
    for (const Listener& l : packet.listening) {
      Node& s = *l.node;
      const model::Servo& servo = *s.servo;
      // A block for a servo's Secondary ID is its group's too, RAM only, unless the packet has
      // a block for its own ID, which has priority (docs/bus.md "Secondary (Shadow) ID").
      const bool own = servo.id() == id;
      const bool group = !own && servo.secondary_id() == id &&
                         std::find(listed.begin(), listed.end(), servo.id()) == listed.end() &&
                         !servo.table().touches_eeprom(address, data.size());
      if (!own && !group) {
        continue;
      }
      s.servo->write_part(address, data);
      if (faulty()) {
        faults_->wrote(packet.heard, s.index, address, data);
      }
      settle(s, false, packet.heard.end);
    }
  };
  std::vector<std::uint8_t> done;  // Bulk Write: one write per ID, the first listed
  std::visit(
      [&](const auto& ins) {
        using T = std::decay_t<decltype(ins)>;
        if constexpr (std::is_same_v<T, wire::SyncWrite>) {
          for (const wire::SyncWriteTarget& t : ins.targets) {
            write_to(t.id, ins.address, t.data);
          }
        } else if constexpr (std::is_same_v<T, wire::BulkWrite>) {
          for (const wire::BulkWriteTarget& t : ins.targets) {
            if (std::find(done.begin(), done.end(), t.id) == done.end()) {
              done.push_back(t.id);
              write_to(t.id, t.address, t.data);
            }
          }
        }
      },
      packet.heard.decoded->instruction);
}

}  // namespace dxlemu::bus
