#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <vector>

#include "bus/bus_stats.hpp"
#include "bus/byte_link.hpp"
#include "bus/fault_hooks.hpp"
#include "bus/heard_packet.hpp"
#include "bus/read_request.hpp"
#include "model/servo.hpp"
#include "sim/scheduler.hpp"
#include "wire/frame.hpp"
#include "wire/framer.hpp"

namespace dxlemu::bus {

/// How a bus times its replies (docs/bus.md "Reply timing").
enum class ReplyTiming {
  /// As real servos: instruction wire time, processing, Return Delay Time, status wire time.
  Modelled,
  /// Every reply is due the moment its instruction has arrived (the daemon's `fast` and `manual`
  /// timing modes). Order, chaining and collisions are unchanged; only the delays are zero.
  Immediate,
};

/// Sees what crosses the line, for traces: set with Bus::set_observer; empty members are skipped.
struct LineObserver {
  /// A packet the framers heard from the client, or a framing failure (garbage skipped while
  /// searching for a header is only counted, not reported).
  std::function<void(const wire::FramerEvent& event)> heard;
  /// Bytes delivered to the client at `at` (a status, a Fast reply, or colliding replies), sent by
  /// servos speaking `protocol`.
  std::function<void(std::span<const std::uint8_t> bytes, sim::SimTime at, wire::Protocol protocol)>
      sent;
};

/// One port: the servos on it, the framers that hear the client, and the timing of every reply on
/// the virtual clock. Receives the client's bytes, decides which servos are addressed, lets them
/// execute, and schedules their status packets when real servos would have put them on the wire.
/// Rules and timing: docs/bus.md.
class Bus {
 public:
  /// A bus that takes time from `scheduler` and sends replies through `link`; both must outlive it.
  Bus(sim::Scheduler& scheduler, ByteLink& link);
  Bus(const Bus&) = delete;
  Bus& operator=(const Bus&) = delete;
  ~Bus();

  /// Adds a servo to the bus and returns it. Two servos may share an ID (their replies collide).
  model::Servo& add_servo(std::unique_ptr<model::Servo> servo);

  /// The client wrote `bytes`, which arrived at `at` (the scheduler's time) while the client's
  /// serial port was set to `client_bps`. No bytes: nothing reaches the line (no collision).
  void receive(std::span<const std::uint8_t> bytes, sim::SimTime at, std::uint32_t client_bps);

  /// The servos, in the order they were added.
  const std::vector<std::unique_ptr<model::Servo>>& servos() const { return servos_; }

  /// True while `servo` is booting after Reboot, Factory Reset, Backup restore or power-on
  /// (silent).
  bool booting(const model::Servo& servo) const;

  /// Unplugs `servo` (its cable carries power and data): it hears and answers nothing and its
  /// motor gives no torque until power_on(). Nothing happens if it is already unplugged.
  void detach(model::Servo& servo);
  /// Plugs `servo` in, or power-cycles it if it is plugged in: it powers on as after a reboot
  /// (RAM to initial values or the backup, Startup Configuration) and is silent while it boots.
  void power_on(model::Servo& servo);
  /// Executes `packet` on `servo` now, as if it were addressed to that servo alone, without
  /// putting anything on the line: its effects, including a new ID or baud and a reboot, apply
  /// as when its status goes out (the control API's servo.reboot and servo.factory_reset).
  /// Returns what the servo would have answered.
  model::ServoResponse instruct(model::Servo& servo, const wire::InstructionPacket& packet);
  /// False while `servo` is unplugged.
  bool attached(const model::Servo& servo) const;

  /// Chooses how replies are timed; Modelled unless set.
  void set_reply_timing(ReplyTiming timing) { timing_ = timing; }

  /// Reports every packet both ways to `observer` from now on (replaces any earlier one).
  void set_observer(LineObserver observer) { observer_ = std::move(observer); }

  /// Asks `hooks` (owned by the caller; it must outlive the bus, or be replaced by nullptr
  /// first) at every fault hook point from now on (faults::PortFaults applies a port's fault
  /// rules: docs/faults.md); nullptr, as at the start: no faults.
  void set_faults(FaultHooks* hooks) { faults_ = hooks; }

  /// Brings every servo's motion up to the scheduler's time (before reading a servo from
  /// outside the bus, e.g. the control API).
  void catch_up() { catch_up(scheduler_.now()); }
  /// Counters since the bus was made.
  BusStats stats() const;

 private:
  struct Node;  // a servo on the line and its bus-side state
  Node* node_of(const model::Servo& servo) const;
  struct Outgoing;
  /// A servo that hears the packet being handled, and how (the fault hooks' answer).
  struct Listener {
    Node* node = nullptr;
    Hearing hearing;
  };
  /// The packet being handled: what was heard, when it ended on the line, and which servos hear
  /// it (on the line at its baud and protocol, awake, not silenced by a fault), in bus order.
  struct Packet {
    HeardPacket heard;
    std::vector<Listener> listening;
  };
  struct Reply {
    Node* node = nullptr;
    model::ServoResponse response;
    std::vector<std::uint8_t> bytes;
    sim::SimDuration extra_delay{0};  // injected extra processing time
  };
  /// The replies that go out at the same time, one group after the other in a chain: normally
  /// one reply; several when servos share an ID, and then their bytes collide.
  using ReplyGroup = std::vector<Reply>;

  // Framing (bus.cpp).
  void handle(const std::vector<wire::FramerEvent>& events);
  /// Cancels every reply not yet delivered and counts a collision, if there was any.
  void drop_pending_replies();
  void schedule_expiry();
  /// Runs every servo's motion up to `now`.
  void catch_up(sim::SimTime now);
  /// True when the fault hooks may change something (FaultHooks::active): every hook is skipped
  /// otherwise.
  bool faulty() const { return faults_ != nullptr && faults_->active(); }
  void rearm_watchdogs(const Packet& packet);
  void disarm_watchdog(Node& node);

  // Who hears a packet (bus_hearing.cpp).
  /// The packet as the servos on the line meet it; no fault hook has run yet.
  Packet arrival(wire::Protocol protocol, std::uint8_t id, std::uint8_t instruction,
                 const wire::InstructionPacket* decoded, sim::SimTime end) const;
  /// The servo hook: drops from `packet.listening` the servos it is for that a fault silences,
  /// and notes how the others take it.
  void hear(Packet& packet);
  /// The IDs a packet is for, as the instruction hook matches them.
  static std::vector<std::uint8_t> fault_ids(const Packet& packet);
  /// True when a unicast of `protocol` can be for `id` (its row's unicast IDs).
  static bool unicast_reaches(wire::Protocol protocol, std::uint8_t id);
  /// The listeners whose ID is `id`, none when `id` is no unicast ID of the packet's protocol.
  static std::vector<const Listener*> addressed(const Packet& packet, std::uint8_t id);
  void on_frame(const wire::Frame& frame);
  void on_bad_check(const wire::FramingError& error);
  /// A packet with a broken CRC or checksum (`instruction`: its unverified instruction byte).
  void answer_bad_check(Packet& packet, std::optional<std::uint8_t> instruction);
  void refuse(const Packet& packet, const wire::DecodeError& error);

  // What servos do with it (bus_instructions.cpp).
  void single(const Packet& packet);
  void group_read(const Packet& packet);
  void fast_read(const Packet& packet, const std::vector<ReadPart>& parts,
                 const std::vector<ReplyGroup>& answered);
  void group_write(const Packet& packet);

  // Replies (bus_replies.cpp).
  void answer(const Packet& packet, const std::vector<ReplyGroup>& groups,
              sim::SimTime start_after);
  /// A servo whose deferred effects apply when a reply goes out, and whether it then reboots.
  struct Settlement {
    Node* node;
    bool reboot;
  };
  /// Delivers `bytes`, which crossed the line at `bps`, at `at`.
  void send_at(std::vector<std::uint8_t> bytes, sim::SimTime at, std::uint32_t bps,
               wire::Protocol protocol, std::vector<Settlement> settlements, bool is_reply = true);
  void settle(Node& node, bool reboot, sim::SimTime at);
  /// Reboots `node`'s servo at `at`: it is silent while it boots.
  void restart(Node& node, sim::SimTime at);
  /// The reply of `listener`'s servo to `heard`.
  Reply reply_of(const HeardPacket& heard, const Listener& listener,
                 model::ServoResponse response) const;
  std::vector<std::uint8_t> status_bytes(const HeardPacket& heard, const Node& node,
                                         const model::ServoResponse& response) const;
  /// The protocol a node's status packets use (as it speaks when the instruction arrives).
  static wire::Protocol status_protocol(const Node& node);
  /// Wire time of `bytes` at `bps`, or zero under ReplyTiming::Immediate.
  sim::SimDuration line_time(std::size_t bytes, std::uint32_t bps) const;
  /// When an instruction's last byte has crossed the line.
  sim::SimTime line_end(const wire::Frame& frame) const;
  /// A servo's processing time plus its Return Delay Time (zero under Immediate), plus any
  /// injected delay.
  sim::SimDuration turnaround(const Reply& reply) const;

  sim::Scheduler& scheduler_;
  ByteLink& link_;
  std::vector<std::unique_ptr<model::Servo>> servos_;
  std::vector<std::unique_ptr<Node>> nodes_;
  /// One framer per row of the protocol table, in its order (FEETECH's frame is the 1.0 frame;
  /// its own framer names the packets FEETECH's). Each hears the line only while a servo speaks
  /// its protocol.
  std::vector<wire::Framer> framers_;
  std::vector<std::shared_ptr<Outgoing>> outgoing_;  // replies scheduled and not yet delivered
  /// The modelled time of the last delivery: a later one is never stamped before it, even when
  /// its own modelled time had passed before it could be scheduled.
  sim::SimTime last_sent_{};
  std::optional<sim::Scheduler::EventId> expiry_;  // the framers' inter-byte timeout
  /// The client's serial rate as of its last write: the rate of the bytes being framed.
  std::uint32_t client_bps_ = 0;
  BusStats stats_;
  ReplyTiming timing_ = ReplyTiming::Modelled;
  LineObserver observer_;
  /// Where the fault hooks are asked; null: no faults.
  FaultHooks* faults_ = nullptr;
};

}  // namespace dxlemu::bus
