#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "model/motion/hardware_fault.hpp"
#include "sim/sim_time.hpp"

namespace dxlemu::faults {

/// What a fault rule does when it fires (docs/faults.md). Wire faults change what crosses the line;
/// servo faults change what a servo does.
enum class Action : std::uint8_t {
  DropReply,           ///< the servo's status never reaches the client
  DelayReply,          ///< the status goes out `delay` later (and the chain after it)
  CorruptCrc,          ///< the status's CRC (2.0) or checksum (1.0) is wrong
  FlipBits,            ///< `bits` random bits of the status are inverted
  TruncateReply,       ///< only the first `bytes` bytes of the status arrive
  GarbageBefore,       ///< `data` (or `bytes` random bytes) arrive just before the status
  DuplicateReply,      ///< the status arrives twice, back to back
  WrongId,             ///< the status carries ID `id` (a valid packet from the wrong servo)
  EchoInstruction,     ///< the client reads its own instruction back (half-duplex adapter)
  Noise,               ///< `bytes` random bytes reach the client after the instruction
  CorruptInstruction,  ///< the servos hear the instruction with a wrong CRC or checksum
  HardwareError,       ///< the servo detects hardware fault `kind` while the rule is active
  Silence,             ///< the servo neither hears nor answers the packet
  SilenceUntilReboot,  ///< the servo goes silent until a Reboot or a power cycle
  Slow,                ///< the servo takes `delay` longer to process the packet
  EepromBusy,          ///< after an EEPROM write the servo is deaf for `per_byte` per byte
  /// A Modbus RTU servo refuses the request unexecuted, answering exception `code` (never matches
  /// a packet of another protocol).
  ModbusException,
};

/// The snake_case name of `action` ("drop_reply"), as in rules.
std::string_view action_name(Action action);
/// The action called `name`, or nullopt.
std::optional<Action> action_from_name(std::string_view name);
/// Every action, in declaration order (for help texts and tests).
const std::vector<Action>& all_actions();

/// True for actions that are a state of the servo (hardware_error) rather than something that
/// happens to one packet.
constexpr bool is_state_fault(Action action) {
  return action == Action::HardwareError;
}

/// Which traffic a rule applies to. An empty member matches everything.
struct Match {
  std::optional<std::string> port;   ///< the port's name in the config ("dxl0")
  std::vector<std::uint8_t> servos;  ///< servo IDs (the IDs they have when the packet arrives)
  /// Instruction names (wire::instruction_name): a packet matches by the name its instruction
  /// byte has in the port's protocol.
  std::vector<std::string> instructions;
  /// Control table addresses, both inclusive: matches an instruction whose data overlaps them.
  std::optional<std::pair<std::uint16_t, std::uint16_t>> address;
};

/// When a matching packet makes the rule fire. All conditions must hold.
struct Trigger {
  double probability = 1.0;            ///< chance per matching packet, from the rule's own stream
  std::optional<std::uint64_t> count;  ///< fire at most this many times
  std::uint64_t after = 0;             ///< let this many matching packets pass first
  /// Active from this long after the rule was added (simulated time).
  sim::SimDuration from{0};
  /// Inactive from this long after the rule was added; nullopt: no end.
  std::optional<sim::SimDuration> until;
};

/// modbus_exception's code unless a rule gives one: 06, Server Device Busy (modbus-rtu.md
/// "Exception responses"), what a busy device answers.
inline constexpr std::uint8_t kDefaultExceptionCode = 0x06;

/// One fault rule: what to do, to which traffic, when. Parameters irrelevant to the action keep
/// their defaults.
struct Rule {
  Action action = Action::DropReply;
  Match match;
  Trigger trigger;
  sim::SimDuration delay{0};         ///< delay_reply, slow
  std::uint32_t bits = 1;            ///< flip_bits
  std::optional<std::size_t> bytes;  ///< truncate_reply (bytes kept), garbage_before, noise
  std::vector<std::uint8_t> data;    ///< garbage_before: these bytes instead of random ones
  std::optional<std::uint8_t> id;    ///< wrong_id; nullopt: the servo's own ID + 1
  model::HardwareFault kind = model::HardwareFault::Overheating;  ///< hardware_error
  sim::SimDuration per_byte{0};  ///< eeprom_busy: deaf time per EEPROM byte written
  /// modbus_exception: the exception code (06: Server Device Busy).
  std::uint8_t code = kDefaultExceptionCode;
};

}  // namespace dxlemu::faults
