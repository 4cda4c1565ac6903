#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "bus/fault_hooks.hpp"
#include "faults/injector.hpp"
#include "model/servo.hpp"
#include "sim/scheduler.hpp"
#include "wire/protocol.hpp"

namespace dxlemu::faults {

/// The fault rules as one port applies them, and the fault state they leave on its servos
/// (silent until a reboot, busy writing EEPROM, injected hardware errors): the bus's fault hooks
/// (bus::FaultHooks), answered from the rules of an Injector. Rules: docs/faults.md.
class PortFaults : public bus::FaultHooks {
 public:
  /// The servos of a port, in the order the bus numbers them (Bus::servos()).
  using Servos = std::vector<std::unique_ptr<model::Servo>>;

  /// Fault state for the servos in `servos` (the bus's own list, read as it grows), whose time
  /// windows run on `scheduler`; both must outlive it. No rules apply until set_rules().
  PortFaults(sim::Scheduler& scheduler, const Servos& servos);
  ~PortFaults() override;

  /// Applies the rules of `injector` (owned by the caller; it must outlive this, or be replaced
  /// by nullptr first) to the servos of the port that rules name `port`, and follows every later
  /// change of the rules at once.
  void set_rules(Injector* injector, std::string port);
  /// True when some rule is set, or a servo is silent until reboot or has been busy writing
  /// EEPROM (until it is powered on): only then may a hook change something.
  bool active() const override {
    return injector_ != nullptr && (!injector_->rules().empty() || stateful_);
  }

  /// False while servo `servo` is busy writing EEPROM at `at` (eeprom_busy).
  bool available(std::size_t servo, sim::SimTime at) const override;
  /// The instruction rules' effects (corrupt_instruction, echo_instruction, noise).
  bus::InstructionEffects instruction(const bus::HeardPacket& packet,
                                      std::vector<std::uint8_t> ids) override;
  /// The servo rules' answer (silence, silence_until_reboot, slow, modbus_exception), and a
  /// silence until reboot that an earlier one left.
  bus::Hearing hear(const bus::HeardPacket& packet, std::size_t servo) override;
  /// EEPROM bytes the servo stored may keep it deaf for a while (eeprom_busy).
  void wrote(const bus::HeardPacket& packet, std::size_t servo, std::uint16_t address,
             std::span<const std::uint8_t> data) override;
  /// The reply rules' effects (drop_reply, delay_reply, and the ones that damage the bytes).
  bus::ReplyEffects reply(const bus::HeardPacket& packet, std::vector<std::uint8_t> ids,
                          std::vector<std::uint8_t>& bytes, wire::Protocol protocol,
                          sim::SimTime at) override;

  /// Ends a silence until reboot.
  void rebooted(std::size_t servo) override;
  /// Ends a silence until reboot and an EEPROM write in progress.
  void powered_on(std::size_t servo) override;
  /// Sets every servo's injected hardware errors as the rules set them at `now`.
  /// hardware_error rules follow a servo's ID, which an instruction may have changed.
  void follow(sim::SimTime now) override;

  /// How often a rule acted on a packet or a servo's handling of it.
  std::uint64_t injected() const override { return injected_; }

 private:
  /// The fault state of one servo that outlives a packet.
  struct ServoFaultState {
    bool silent_until_reboot = false;  // hears nothing but a Reboot until it reboots
    sim::SimTime deaf_until{};         // busy writing EEPROM
  };

  /// Servo `servo`'s fault state (kept for the servos the bus has, by their number).
  ServoFaultState& state_of(std::size_t servo);
  /// Notes whether any servo has fault state left (for active()).
  void note_state();
  /// Brings every servo's hardware errors in line with the rules at the scheduler's time and
  /// schedules the next change a rule's time window makes.
  void refresh();
  /// Sets every servo's injected hardware errors from the rules at `now`.
  void apply_hardware_faults(sim::SimTime now);
  /// The facts of `packet` for the servos with `ids`, at `at`.
  PacketFacts facts(const bus::HeardPacket& packet, std::vector<std::uint8_t> ids,
                    sim::SimTime at) const;
  /// Counts the hook calls on which some rule acted.
  void count(bool acted) { injected_ += acted ? 1 : 0; }

  sim::Scheduler& scheduler_;
  const Servos& servos_;
  Injector* injector_ = nullptr;
  std::string port_;
  std::uint64_t subscription_ = 0;
  std::vector<ServoFaultState> states_;            // by servo number; grows with the bus's servos
  bool stateful_ = false;                          // some entry of states_ is not the default
  std::optional<sim::Scheduler::EventId> window_;  // next change of a hardware_error rule
  std::uint64_t injected_ = 0;
};

}  // namespace dxlemu::faults
