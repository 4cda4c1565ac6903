#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <vector>

#include "bus/bus_stats.hpp"
#include "bus/byte_link.hpp"
#include "faults/injector.hpp"
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
  /// serial port was set to `client_bps`.
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
  /// False while `servo` is unplugged.
  bool attached(const model::Servo& servo) const;

  /// Chooses how replies are timed; Modelled unless set.
  void set_reply_timing(ReplyTiming timing) { timing_ = timing; }

  /// Reports every packet both ways to `observer` from now on (replaces any earlier one).
  void set_observer(LineObserver observer) { observer_ = std::move(observer); }

  /// Applies the rules of `injector` (owned by the caller; must outlive the bus, or be replaced
  /// by nullptr first) to this bus, whose port rules name `port` (docs/faults.md). The bus follows
  /// every later change of the rules by itself.
  void set_faults(faults::Injector* injector, std::string port);

  /// Brings every servo's motion up to the scheduler's time (before reading a servo from
  /// outside the bus, e.g. the control API).
  void catch_up() { catch_up(scheduler_.now()); }
  /// Counters since the bus was made.
  const BusStats& stats() const { return stats_; }

 private:
  struct Station;  // a servo and its bus-side state
  Station* station_of(const model::Servo& servo) const;
  struct Outgoing;
  struct Reply {
    Station* station;
    model::ServoResponse response;
    std::vector<std::uint8_t> bytes;
  };

  /// What the packet being handled is, for the fault hooks. Meaningful only while a packet is
  /// handled (the fault hooks run synchronously inside on_frame and on_bad_check).
  struct Current {
    std::uint8_t instruction = 0;
    const wire::InstructionPacket* packet = nullptr;  // nullptr when it could not be decoded
  };

  void handle(const std::vector<wire::FramerEvent>& events, std::uint32_t client_bps);
  /// Cancels every reply not yet delivered and counts a collision, if there was any.
  void drop_pending_replies();
  /// Clears the previous packet's servo faults (before the next packet is heard).
  void forget_servo_faults();
  /// Fault hooks when a packet with `packet_id` and `protocol` is heard: decides for each
  /// servo it is for whether it hears it (silence, silence_until_reboot) and how slowly.
  void hear(wire::Protocol protocol, std::uint8_t packet_id, std::uint32_t client_bps,
            sim::SimTime end);
  /// Fault facts about the current packet, for the servos with `ids`.
  faults::PacketFacts facts(std::vector<std::uint8_t> ids, sim::SimTime at) const;
  /// eeprom_busy: after `station` wrote `data` at `address`, it may stay deaf for a while.
  void after_write(Station& station, std::uint16_t address, std::span<const std::uint8_t> data,
                   sim::SimTime end);
  /// Applies the reply faults to `bytes` from the servos with `ids`; returns the extra delay and
  /// whether they were dropped.
  faults::ReplyEffects mangle(std::vector<std::uint8_t> ids, std::vector<std::uint8_t>& bytes,
                              wire::Protocol protocol);
  /// Brings every servo's injected hardware errors in line with the rules at the scheduler's time
  /// and schedules the next change a rule's time window makes.
  void refresh_faults();
  /// Sets every servo's injected hardware errors from the rules at `now`.
  void apply_hardware_faults(sim::SimTime now);
  /// Runs every servo's motion up to `now`.
  void catch_up(sim::SimTime now);
  void schedule_expiry(std::uint32_t client_bps);
  void rearm_watchdogs(wire::Protocol protocol, std::uint32_t client_bps, sim::SimTime now);
  void on_frame(const wire::Frame& frame, std::uint32_t client_bps);
  void on_bad_check(const wire::FramingError& error, sim::SimTime line_end,
                    std::uint32_t client_bps);
  std::vector<Station*> listeners(wire::Protocol protocol, std::uint32_t client_bps,
                                  sim::SimTime now);
  std::vector<Station*> addressed(const std::vector<Station*>& listening, std::uint8_t id) const;
  void single(const wire::InstructionPacket& packet, sim::SimTime line_end,
              std::uint32_t client_bps);
  void group_read(const wire::InstructionPacket& packet, sim::SimTime line_end,
                  std::uint32_t client_bps);
  void group_write(const wire::InstructionPacket& packet, sim::SimTime line_end,
                   std::uint32_t client_bps);
  /// The replies that go out in one time slot: normally one; several when servos share an ID,
  /// and then their bytes collide.
  using Slot = std::vector<Reply>;
  void answer(const std::vector<Slot>& slots, sim::SimTime start_after);
  /// A servo whose deferred effects apply when a reply goes out, and whether it then reboots.
  struct Settlement {
    Station* station;
    bool reboot;
  };
  void send_at(std::vector<std::uint8_t> bytes, sim::SimTime at, wire::Protocol protocol,
               std::vector<Settlement> settlements, bool is_reply = true);
  void settle(Station& station, bool reboot, sim::SimTime at);
  std::vector<std::uint8_t> status_bytes(const Station& station,
                                         const model::ServoResponse& response) const;
  /// The protocol a station's status packets use (as it speaks when the instruction arrives).
  static wire::Protocol status_protocol(const Station& station);
  /// Wire time of `bytes` at `bps`, or zero under ReplyTiming::Immediate.
  sim::SimDuration line_time(std::size_t bytes, std::uint32_t bps) const;
  /// When an instruction's last byte has crossed the line.
  sim::SimTime line_end(const wire::Frame& frame, std::uint32_t bps) const;
  /// A servo's processing time plus its Return Delay Time, or zero under Immediate.
  sim::SimDuration turnaround(const Reply& reply) const;

  sim::Scheduler& scheduler_;
  ByteLink& link_;
  std::vector<std::unique_ptr<model::Servo>> servos_;
  std::vector<std::unique_ptr<Station>> stations_;
  wire::Framer v1_framer_{wire::Protocol::V1};
  wire::Framer v2_framer_{wire::Protocol::V2};
  std::vector<std::shared_ptr<Outgoing>> outgoing_;  // replies scheduled and not yet delivered
  std::optional<sim::Scheduler::EventId> expiry_;    // the framers' inter-byte timeout
  BusStats stats_;
  ReplyTiming timing_ = ReplyTiming::Modelled;
  LineObserver observer_;
  faults::Injector* injector_ = nullptr;
  std::string port_;  // this bus's name in fault rules
  std::uint64_t fault_subscription_ = 0;
  Current current_;
  std::optional<sim::Scheduler::EventId> fault_window_;  // next change of a hardware_error rule
};

}  // namespace dxlemu::bus
