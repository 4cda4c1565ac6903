#include "faults/injector.hpp"

#include <algorithm>

#include "faults/packet_mangling.hpp"

namespace dxlemu::faults {

bool matches(const Match& match, const PacketFacts& facts) {
  if (match.port && *match.port != facts.port) {
    return false;
  }
  if (!match.servos.empty() &&
      std::none_of(facts.ids.begin(), facts.ids.end(), [&](std::uint8_t id) {
        return std::find(match.servos.begin(), match.servos.end(), id) != match.servos.end();
      })) {
    return false;
  }
  if (!match.instructions.empty() &&
      std::find(match.instructions.begin(), match.instructions.end(),
                wire::instruction_name(facts.protocol, facts.instruction)) ==
          match.instructions.end()) {
    return false;
  }
  if (match.address) {
    // Only instructions that touch the control table have a span to overlap.
    if (!facts.span || facts.span->second < match.address->first ||
        facts.span->first > match.address->second) {
      return false;
    }
  }
  return true;
}

bool in_window(const Trigger& trigger, sim::SimTime added, sim::SimTime now) {
  const sim::SimDuration elapsed = now - added;
  return elapsed >= trigger.from && (!trigger.until || elapsed < *trigger.until);
}

Injector::Injector(std::uint64_t seed) : rng_(seed) {}

std::uint64_t Injector::add(Rule rule, sim::SimTime now) {
  const std::uint64_t id = next_id_++;
  sim::RandomStream* stream = &rng_.stream("fault/" + std::to_string(id));
  rules_.push_back({id, std::move(rule), now, 0, 0, stream});
  changed();
  return id;
}

bool Injector::remove(std::uint64_t id) {
  const auto removed = std::erase_if(rules_, [id](const Entry& e) { return e.id == id; });
  if (removed != 0) {
    changed();
  }
  return removed != 0;
}

std::size_t Injector::clear() {
  const std::size_t n = rules_.size();
  rules_.clear();
  changed();
  return n;
}

std::uint64_t Injector::subscribe(std::function<void()> listener) {
  listeners_.emplace_back(next_listener_, std::move(listener));
  return next_listener_++;
}

void Injector::unsubscribe(std::uint64_t key) {
  std::erase_if(listeners_, [key](const auto& l) { return l.first == key; });
}

void Injector::changed() {
  // A copy: a listener may subscribe or unsubscribe while it is called.
  const auto listeners = listeners_;
  for (const auto& [key, listener] : listeners) {
    listener();
  }
}

bool Injector::fires(Entry& entry, const PacketFacts& facts) {
  if (!matches(entry.rule.match, facts) || !in_window(entry.rule.trigger, entry.added, facts.at)) {
    return false;
  }
  // Only a protocol whose refusals are exception codes has an exception response to send: on
  // the others the rule does not match (nor count) at all.
  if (entry.rule.action == Action::ModbusException &&
      wire::traits(facts.protocol).status.shape != wire::StatusShape::ExceptionCode) {
    return false;
  }
  const Trigger& t = entry.rule.trigger;
  ++entry.matched;
  if (entry.matched <= t.after || (t.count && entry.fired >= *t.count) ||
      !entry.stream->bernoulli(t.probability)) {
    return false;
  }
  ++entry.fired;
  return true;
}

void Injector::fire(std::initializer_list<Action> actions, const PacketFacts& facts,
                    const std::function<void(Entry&)>& apply) {
  for (Entry& e : rules_) {
    if (std::find(actions.begin(), actions.end(), e.rule.action) != actions.end() &&
        fires(e, facts)) {
      apply(e);
    }
  }
}

bus::InstructionEffects Injector::instruction(const PacketFacts& facts) {
  bus::InstructionEffects out;
  fire({Action::CorruptInstruction, Action::EchoInstruction, Action::Noise}, facts, [&](Entry& e) {
    if (e.rule.action == Action::CorruptInstruction) {
      out.corrupt = true;
    } else if (e.rule.action == Action::EchoInstruction) {
      out.echo = true;
    } else {
      const auto noise = random_bytes(e.rule.bytes.value_or(1), *e.stream);
      out.noise.insert(out.noise.end(), noise.begin(), noise.end());
    }
  });
  return out;
}

ServoEffects Injector::servo(const PacketFacts& facts) {
  ServoEffects out;
  fire({Action::Silence, Action::SilenceUntilReboot, Action::Slow, Action::ModbusException}, facts,
       [&](Entry& e) {
         if (e.rule.action == Action::Silence) {
           out.silence = true;
         } else if (e.rule.action == Action::SilenceUntilReboot) {
           out.silence_until_reboot = true;
         } else if (e.rule.action == Action::ModbusException) {
           // The oldest rule's code: one exception response carries one code.
           out.exception = out.exception != 0 ? out.exception : e.rule.code;
         } else {
           out.slow += e.rule.delay;
         }
       });
  return out;
}

sim::SimDuration Injector::eeprom_write(const PacketFacts& facts, std::size_t eeprom_bytes) {
  sim::SimDuration deaf{0};
  fire({Action::EepromBusy}, facts, [&](Entry& e) {
    deaf = std::max(deaf, e.rule.per_byte * static_cast<std::int64_t>(eeprom_bytes));
  });
  return deaf;
}

bus::ReplyEffects Injector::reply(const PacketFacts& facts, std::vector<std::uint8_t>& packet,
                                  wire::Protocol protocol) {
  bus::ReplyEffects out;
  std::vector<std::uint8_t> before;  // garbage_before, in rule order
  bool duplicate = false;
  fire({Action::DropReply, Action::DelayReply, Action::CorruptCrc, Action::FlipBits,
        Action::TruncateReply, Action::GarbageBefore, Action::DuplicateReply, Action::WrongId},
       facts, [&](Entry& e) {
         const Rule& r = e.rule;
         out.any = true;
         switch (r.action) {
           case Action::DropReply:
             out.dropped = true;
             break;
           case Action::DelayReply:
             out.delay += r.delay;
             break;
           case Action::CorruptCrc:
             break_check(packet);
             break;
           case Action::FlipBits:
             flip_bits(packet, r.bits, *e.stream);
             break;
           case Action::TruncateReply: {
             // Without "bytes", somewhere inside the packet: at least one byte arrives, one is
             // lost.
             const std::size_t last = std::max<std::size_t>(packet.size(), 2) - 1;
             const std::size_t keep =
                 r.bytes ? *r.bytes : static_cast<std::size_t>(e.stream->uniform(1, last));
             packet.resize(std::min(keep, packet.size()));
             break;
           }
           case Action::GarbageBefore: {
             const auto garbage = r.data.empty() ? random_bytes(*r.bytes, *e.stream) : r.data;
             before.insert(before.end(), garbage.begin(), garbage.end());
             break;
           }
           case Action::DuplicateReply:
             duplicate = true;
             break;
           case Action::WrongId: {
             const std::uint8_t own = facts.ids.empty() ? 0 : facts.ids.front();
             set_id(packet, protocol, r.id.value_or(static_cast<std::uint8_t>((own + 1) % 0xFD)));
             break;
           }
           default:
             break;
         }
       });
  if (duplicate) {
    const std::vector<std::uint8_t> copy = packet;
    packet.insert(packet.end(), copy.begin(), copy.end());
  }
  packet.insert(packet.begin(), before.begin(), before.end());
  if (out.dropped) {
    packet.clear();
  }
  return out;
}

model::FaultSet Injector::hardware_faults(std::string_view port, std::uint8_t id,
                                          sim::SimTime now) const {
  model::FaultSet out = 0;
  const PacketFacts facts{port, 0, {id}, std::nullopt, now};
  for (const Entry& e : rules_) {
    if (e.rule.action == Action::HardwareError && matches(e.rule.match, facts) &&
        in_window(e.rule.trigger, e.added, now)) {
      out |= model::fault_set(e.rule.kind);
    }
  }
  return out;
}

std::optional<sim::SimTime> Injector::next_state_change(sim::SimTime now) const {
  std::optional<sim::SimTime> next;
  const auto consider = [&](sim::SimTime t) {
    if (t > now && (!next || t < *next)) {
      next = t;
    }
  };
  for (const Entry& e : rules_) {
    if (is_state_fault(e.rule.action)) {
      consider(e.added + e.rule.trigger.from);
      if (e.rule.trigger.until) {
        consider(e.added + *e.rule.trigger.until);
      }
    }
  }
  return next;
}

}  // namespace dxlemu::faults
