#include "faults/port_faults.hpp"

#include <algorithm>

#include "faults/packet_facts.hpp"

namespace dxlemu::faults {

PortFaults::PortFaults(sim::Scheduler& scheduler, const Servos& servos)
    : scheduler_(scheduler), servos_(servos) {}

PortFaults::~PortFaults() {
  if (injector_ != nullptr) {
    injector_->unsubscribe(subscription_);
  }
}

void PortFaults::set_rules(Injector* injector, std::string port) {
  if (injector_ != nullptr) {
    injector_->unsubscribe(subscription_);
  }
  injector_ = injector;
  port_ = std::move(port);
  if (injector_ != nullptr) {
    subscription_ = injector_->subscribe([this] { refresh(); });
  }
  refresh();
}

PortFaults::ServoFaultState& PortFaults::state_of(std::size_t servo) {
  if (servo >= states_.size()) {
    states_.resize(servos_.size());
  }
  return states_[servo];
}

void PortFaults::note_state() {
  stateful_ = std::any_of(states_.begin(), states_.end(), [](const ServoFaultState& s) {
    return s.silent_until_reboot || s.deaf_until != sim::SimTime{};
  });
}

bool PortFaults::available(std::size_t servo, sim::SimTime at) const {
  return servo >= states_.size() || at >= states_[servo].deaf_until;
}

PacketFacts PortFaults::facts(const bus::HeardPacket& packet, std::vector<std::uint8_t> ids,
                              sim::SimTime at) const {
  PacketFacts f{port_, packet.instruction, std::move(ids), std::nullopt, at, packet.protocol};
  if (packet.decoded != nullptr) {
    f.span =
        span_of(*packet.decoded, f.ids.size() == 1 ? std::optional(f.ids.front()) : std::nullopt);
  }
  return f;
}

bus::InstructionEffects PortFaults::instruction(const bus::HeardPacket& packet,
                                                std::vector<std::uint8_t> ids) {
  if (injector_ == nullptr) {
    return {};
  }
  bus::InstructionEffects effects =
      injector_->instruction(facts(packet, std::move(ids), packet.end));
  count(effects.any());
  return effects;
}

bus::Hearing PortFaults::hear(const bus::HeardPacket& packet, std::size_t servo) {
  if (injector_ == nullptr) {
    return {};
  }
  ServoFaultState& s = state_of(servo);
  const std::uint8_t id = servos_[servo]->id();
  const ServoEffects effects = injector_->servo(facts(packet, {id}, packet.end));
  count(effects.any());
  if (effects.silence_until_reboot && !s.silent_until_reboot) {
    s.silent_until_reboot = true;
    stateful_ = true;
  }
  bus::Hearing out{!effects.silence, true, effects.slow, effects.exception};
  if (s.silent_until_reboot) {
    // Its firmware still reacts to a Reboot sent to its own ID, without answering. By what the
    // packet decodes to: 0x08 is Diagnostics in Modbus RTU, which has no Reboot.
    const bool reboot = packet.decoded != nullptr &&
                        std::holds_alternative<wire::Reboot>(packet.decoded->instruction) &&
                        id == packet.id;
    (reboot ? out.answers : out.hears) = false;
  }
  return out;
}

void PortFaults::wrote(const bus::HeardPacket& packet, std::size_t servo, std::uint16_t address,
                       std::span<const std::uint8_t> data) {
  if (injector_ == nullptr) {
    return;
  }
  const model::Servo& written = *servos_[servo];
  const std::size_t stored = written.table().eeprom_bytes_holding(address, data);
  if (stored == 0) {
    return;
  }
  const sim::SimDuration busy =
      injector_->eeprom_write(facts(packet, {written.id()}, packet.end), stored);
  if (busy.count() > 0) {
    count(true);
    ServoFaultState& s = state_of(servo);
    s.deaf_until = std::max(s.deaf_until, packet.end + busy);
    stateful_ = true;
  }
}

bus::ReplyEffects PortFaults::reply(const bus::HeardPacket& packet, std::vector<std::uint8_t> ids,
                                    std::vector<std::uint8_t>& bytes, wire::Protocol protocol,
                                    sim::SimTime at) {
  if (injector_ == nullptr) {
    return {};
  }
  const bus::ReplyEffects effects =
      injector_->reply(facts(packet, std::move(ids), at), bytes, protocol);
  count(effects.any);
  return effects;
}

void PortFaults::rebooted(std::size_t servo) {
  if (servo < states_.size() && states_[servo].silent_until_reboot) {
    states_[servo].silent_until_reboot = false;
    note_state();
  }
}

void PortFaults::powered_on(std::size_t servo) {
  if (servo < states_.size()) {
    states_[servo] = {};
    note_state();
  }
}

void PortFaults::follow(sim::SimTime now) {
  if (injector_ != nullptr && !injector_->rules().empty()) {
    apply_hardware_faults(now);
  }
}

void PortFaults::refresh() {
  if (window_) {
    scheduler_.cancel(*window_);
    window_.reset();
  }
  const sim::SimTime now = scheduler_.now();
  for (const auto& servo : servos_) {
    servo->advance_to(now);
  }
  apply_hardware_faults(now);
  if (injector_ == nullptr) {
    return;
  }
  if (const auto next = injector_->next_state_change(now)) {
    window_ = scheduler_.schedule_at(*next, [this] {
      window_.reset();
      refresh();
    });
  }
}

void PortFaults::apply_hardware_faults(sim::SimTime now) {
  for (const auto& servo : servos_) {
    const model::FaultSet faults =
        injector_ != nullptr ? injector_->hardware_faults(port_, servo->id(), now) : 0;
    if (faults != servo->motion().injected()) {
      servo->advance_to(now);
      servo->motion().set_injected(faults);
    }
  }
}

}  // namespace dxlemu::faults
