#pragma once

#include <cstdint>
#include <functional>
#include <initializer_list>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "bus/fault_hooks.hpp"
#include "faults/rule.hpp"
#include "model/motion/hardware_fault.hpp"
#include "sim/rng.hpp"
#include "sim/sim_time.hpp"
#include "wire/protocol.hpp"

namespace dxlemu::faults {

/// What the bus knows about a packet when it asks the injector (docs/faults.md "Matching").
struct PacketFacts {
  std::string_view port;
  std::uint8_t instruction = 0;  ///< the instruction byte (unverified for a damaged packet)
  /// The servo IDs it is for: unicast one, broadcast every servo listening, Sync/Bulk the listed
  /// ones. For a servo's own part (servo and reply faults) only that servo's ID.
  std::vector<std::uint8_t> ids;
  /// The control-table addresses it reads or writes, first and last, when it has any.
  std::optional<std::pair<std::uint16_t, std::uint16_t>> span;
  sim::SimTime at{};  ///< when its last byte crossed the line
  /// The port's protocol: what the instruction byte means (DYNAMIXEL's and FEETECH's codes differ).
  wire::Protocol protocol = wire::kDefaultProtocol;
};

/// What happens to one servo's handling of a packet.
struct ServoEffects {
  bool silence = false;               ///< the servo ignores the packet
  bool silence_until_reboot = false;  ///< the servo ignores everything until a Reboot
  sim::SimDuration slow{0};           ///< extra processing time
  /// Not 0: the servo refuses the packet unexecuted with this exception code (modbus_exception).
  std::uint8_t exception = 0;
  bool any() const {
    return silence || silence_until_reboot || slow.count() != 0 || exception != 0;
  }
};

/// The fault rules of a daemon and their state: which fired how often, each rule's own random
/// stream. The bus calls it at its hook points (instruction heard, servo about to execute, reply
/// about to be sent, servo state); the control API adds and removes rules. Each rule draws from
/// its own stream of the seeded generator, so the same seed, rules and traffic give the same
/// faults. Single-threaded, no clock: times come from the caller.
class Injector {
 public:
  /// An injector whose random choices come from `seed` (`--seed`).
  explicit Injector(std::uint64_t seed);

  /// One rule and its counters.
  struct Entry {
    std::uint64_t id = 0;
    Rule rule;
    sim::SimTime added;                   ///< from_ms and until_ms count from here
    std::uint64_t matched = 0;            ///< packets that matched inside the time window
    std::uint64_t fired = 0;              ///< times the action was applied
    sim::RandomStream* stream = nullptr;  ///< owned by the injector's generator
  };

  /// Adds `rule`, active from `now`, and returns its id (1, 2, ...; never reused).
  std::uint64_t add(Rule rule, sim::SimTime now);
  /// Removes rule `id`; false when there is no such rule.
  bool remove(std::uint64_t id);
  /// Removes every rule; returns how many there were.
  std::size_t clear();
  /// The rules, oldest first.
  const std::vector<Entry>& rules() const { return rules_; }
  /// The seed the random choices come from.
  std::uint64_t seed() const { return rng_.seed(); }
  /// Calls `listener` after every change of the rules (add, remove, clear), so that whoever
  /// applies them (each bus's fault state) follows at once, whoever changed them. Returns the
  /// subscription's key for unsubscribe().
  std::uint64_t subscribe(std::function<void()> listener);
  /// Ends subscription `key`; nothing happens when there is none.
  void unsubscribe(std::uint64_t key);

  /// Hook: an instruction packet was heard on `facts.port`.
  bus::InstructionEffects instruction(const PacketFacts& facts);
  /// Hook: a servo (facts.ids holds its ID) is about to hear a packet.
  ServoEffects servo(const PacketFacts& facts);
  /// Hook: a servo wrote `eeprom_bytes` EEPROM bytes; returns how long it stays deaf.
  sim::SimDuration eeprom_write(const PacketFacts& facts, std::size_t eeprom_bytes);
  /// Hook: `packet` (a status of `protocol` from the servos in facts.ids, answering
  /// facts.instruction) is about to go out; damages it in place.
  bus::ReplyEffects reply(const PacketFacts& facts, std::vector<std::uint8_t>& packet,
                          wire::Protocol protocol);

  /// The hardware errors that rules impose on servo `id` of `port` at `now`.
  model::FaultSet hardware_faults(std::string_view port, std::uint8_t id, sim::SimTime now) const;
  /// The first moment after `now` at which hardware_faults() may change by the clock alone (a
  /// rule's window opening or closing), or nullopt.
  std::optional<sim::SimTime> next_state_change(sim::SimTime now) const;

 private:
  /// True when `entry` applies to `facts` now; counts the match and the firing.
  bool fires(Entry& entry, const PacketFacts& facts);
  /// Calls `apply` for every rule with one of `actions` that fires on `facts`, oldest first.
  void fire(std::initializer_list<Action> actions, const PacketFacts& facts,
            const std::function<void(Entry&)>& apply);

  sim::Rng rng_;
  std::vector<Entry> rules_;
  std::uint64_t next_id_ = 1;
  /// Calls every subscriber (after a change of the rules).
  void changed();
  std::vector<std::pair<std::uint64_t, std::function<void()>>> listeners_;
  std::uint64_t next_listener_ = 1;
};

/// True when `match` selects `facts` (port, any of its servos, instruction, overlapping span).
bool matches(const Match& match, const PacketFacts& facts);

/// True while a rule added at `added` is inside its time window at `now`.
bool in_window(const Trigger& trigger, sim::SimTime added, sim::SimTime now);

}  // namespace dxlemu::faults
