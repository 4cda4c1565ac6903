#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "bus/heard_packet.hpp"
#include "sim/sim_time.hpp"
#include "wire/protocol.hpp"

namespace dxlemu::bus {

/// How one servo takes a packet that is for it: the answer of the servo hook.
struct Hearing {
  bool hears = true;    ///< false: the servo ignores the packet
  bool answers = true;  ///< false: it executes the packet but sends no status
  /// Extra processing time before its status (a duration, added to the modelled one).
  sim::SimDuration extra_delay{0};
  /// Not 0: the servo does not execute the packet and answers it as a refusal whose status
  /// carries this code (Modbus RTU: an exception response with this exception code).
  std::uint8_t refusal = 0;
};

/// What happens to an instruction on its way to the servos (and back to the client, for echo).
struct InstructionEffects {
  bool corrupt = false;             ///< the servos hear a wrong CRC or checksum
  bool echo = false;                ///< the client reads the instruction back
  std::vector<std::uint8_t> noise;  ///< random bytes the client reads after the instruction
  /// True when something happens to the instruction.
  bool any() const { return corrupt || echo || !noise.empty(); }
};

/// What happened to one status packet on its way to the client.
struct ReplyEffects {
  bool dropped = false;       ///< nothing arrives
  sim::SimDuration delay{0};  ///< it (and the chain after it) arrives this much later
  bool any = false;           ///< some rule fired (for the bus's counter)
};

/// What a bus asks at its fault hook points, in the order a packet meets them (instruction, hear,
/// wrote, reply), and applies the answers of; addressing and timing stay the bus's. faults/
/// implements it (faults::PortFaults) from fault rules; a bus without one has no faults. Servos
/// are named by their number on the bus: 0, 1, ... in the order they were added (Bus::servos()).
class FaultHooks {
 public:
  FaultHooks() = default;
  FaultHooks(const FaultHooks&) = delete;
  FaultHooks& operator=(const FaultHooks&) = delete;
  virtual ~FaultHooks() = default;

  /// True when some rule or some servo's fault state applies. While false every hook answers
  /// that nothing happens, and the bus skips them all (a port without faults pays nothing).
  virtual bool active() const = 0;

  /// False while servo `servo` is busy writing EEPROM at `at`: it hears nothing.
  virtual bool available(std::size_t servo, sim::SimTime at) const = 0;
  /// Hook: `packet` crossed the line for the servos with `ids` (its ID, the IDs a Sync/Bulk
  /// instruction lists, or every servo listening to a broadcast).
  virtual InstructionEffects instruction(const HeardPacket& packet,
                                         std::vector<std::uint8_t> ids) = 0;
  /// Hook: servo `servo` is about to hear `packet`, which is for it.
  virtual Hearing hear(const HeardPacket& packet, std::size_t servo) = 0;
  /// Hook: servo `servo` executed a write of `data` at `address` (Write, Sync/Bulk Write part).
  virtual void wrote(const HeardPacket& packet, std::size_t servo, std::uint16_t address,
                     std::span<const std::uint8_t> data) = 0;
  /// Hook: `bytes` (a status of `protocol` from the servos with `ids`, answering `packet`) go
  /// out at `at`; damages them in place.
  virtual ReplyEffects reply(const HeardPacket& packet, std::vector<std::uint8_t> ids,
                             std::vector<std::uint8_t>& bytes, wire::Protocol protocol,
                             sim::SimTime at) = 0;

  /// Servo `servo` rebooted.
  virtual void rebooted(std::size_t servo) = 0;
  /// Servo `servo` was powered on (it reboots too).
  virtual void powered_on(std::size_t servo) = 0;
  /// Hook (servo tick): the servos' motion has reached `now`.
  virtual void follow(sim::SimTime now) = 0;

  /// How often a rule acted on a packet or a servo's handling of it (BusStats::faults_injected).
  virtual std::uint64_t injected() const = 0;
};

}  // namespace dxlemu::bus
