#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "faults/injector.hpp"
#include "model/servo.hpp"
#include "sim/scheduler.hpp"
#include "wire/instruction.hpp"
#include "wire/protocol.hpp"

namespace dxlemu::faults {

/// What the bus knows about the packet it is handling, as the fault hooks need it.
struct HeardPacket {
  wire::Protocol protocol = wire::kDefaultProtocol;
  std::uint8_t id = 0;           ///< the packet ID (unverified for a damaged packet)
  std::uint8_t instruction = 0;  ///< the instruction byte (unverified for a damaged packet)
  /// The decoded instruction; nullptr when the packet is damaged or could not be decoded.
  const wire::InstructionPacket* decoded = nullptr;
  sim::SimTime end{};  ///< when its last byte crossed the line
};

/// How one servo takes a packet that is for it: the answer of the servo hook.
struct Hearing {
  bool hears = true;         ///< false: the servo ignores the packet
  bool answers = true;       ///< false: it executes the packet but sends no status
  sim::SimDuration slow{0};  ///< extra processing time before its status
};

/// The fault rules as one port applies them, and the fault state they leave on its servos
/// (silent until a reboot, busy writing EEPROM, injected hardware errors). The bus calls it at
/// named hook points, in the order a packet meets them (instruction, hear, wrote, reply), and
/// applies the answers; addressing and timing stay the bus's. Rules: docs/faults.md.
class PortFaults {
 public:
  /// Fault state whose time windows run on `scheduler` (which must outlive it). No rules apply
  /// until set_rules().
  explicit PortFaults(sim::Scheduler& scheduler);
  PortFaults(const PortFaults&) = delete;
  PortFaults& operator=(const PortFaults&) = delete;
  ~PortFaults();

  /// Applies the rules of `injector` (owned by the caller; it must outlive this, or be replaced
  /// by nullptr first) to the servos of the port that rules name `port`, and follows every later
  /// change of the rules at once.
  void set_rules(Injector* injector, std::string port);
  /// Adds a servo of the port (which must outlive this) and returns its number for the hooks:
  /// 0, 1, ... in the order they were added.
  std::size_t add_servo(model::Servo& servo);
  /// True when rules apply (an injector is set): the hooks may then change something.
  bool active() const { return injector_ != nullptr; }

  /// False while servo `servo` is busy writing EEPROM at `at` (eeprom_busy): it hears nothing.
  bool available(std::size_t servo, sim::SimTime at) const;

  /// Hook: `packet` crossed the line for the servos with `ids` (its ID, the IDs a Sync/Bulk
  /// instruction lists, or every servo listening to a broadcast).
  InstructionEffects instruction(const HeardPacket& packet, std::vector<std::uint8_t> ids);
  /// Hook: servo `servo` is about to hear `packet`, which is for it.
  Hearing hear(const HeardPacket& packet, std::size_t servo);
  /// Hook: servo `servo` executed a write of `data` at `address` (Write, Sync/Bulk Write part):
  /// EEPROM bytes it stored may keep it deaf for a while.
  void wrote(const HeardPacket& packet, std::size_t servo, std::uint16_t address,
             std::span<const std::uint8_t> data);
  /// Hook: `bytes` (a status of `protocol` from the servos with `ids`, answering `packet`) go out
  /// at `at`; damages them in place.
  ReplyEffects reply(const HeardPacket& packet, std::vector<std::uint8_t> ids,
                     std::vector<std::uint8_t>& bytes, wire::Protocol protocol, sim::SimTime at);

  /// Servo `servo` rebooted: a silence until reboot ends.
  void rebooted(std::size_t servo);
  /// Servo `servo` was powered on: it reboots, and an EEPROM write in progress is over.
  void powered_on(std::size_t servo);
  /// Hook (servo tick): every servo's injected hardware errors as the rules set them at `now`.
  /// hardware_error rules follow a servo's ID, which an instruction may have changed.
  void follow(sim::SimTime now);

  /// How often a rule acted on a packet or a servo's handling of it (BusStats::faults_injected).
  std::uint64_t injected() const { return injected_; }

 private:
  /// A servo and the fault state that outlives a packet.
  struct Station {
    model::Servo* servo = nullptr;
    bool silent_until_reboot = false;  // hears nothing but a Reboot until it reboots
    sim::SimTime deaf_until{};         // busy writing EEPROM
  };

  /// Brings every servo's hardware errors in line with the rules at the scheduler's time and
  /// schedules the next change a rule's time window makes.
  void refresh();
  /// Sets every servo's injected hardware errors from the rules at `now`.
  void apply_hardware_faults(sim::SimTime now);
  /// The facts of `packet` for the servos with `ids`, at `at`.
  PacketFacts facts(const HeardPacket& packet, std::vector<std::uint8_t> ids,
                    sim::SimTime at) const;
  /// Counts the hook calls on which some rule acted.
  void count(bool acted) { injected_ += acted ? 1 : 0; }

  sim::Scheduler& scheduler_;
  Injector* injector_ = nullptr;
  std::string port_;
  std::uint64_t subscription_ = 0;
  std::vector<Station> stations_;
  std::optional<sim::Scheduler::EventId> window_;  // next change of a hardware_error rule
  std::uint64_t injected_ = 0;
};

}  // namespace dxlemu::faults
