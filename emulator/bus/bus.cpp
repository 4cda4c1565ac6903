#include "bus/bus.hpp"

#include <algorithm>
#include <limits>
#include <type_traits>

#include "bus/line_timing.hpp"
#include "faults/packet_facts.hpp"
#include "wire/instruction_decoder.hpp"
#include "wire/packet_encoder.hpp"

namespace dxlemu::bus {

using sim::SimDuration;
using sim::SimTime;

struct Bus::Station {
  model::Servo* servo = nullptr;
  SimTime booting_until{};  // silent before this (Reboot, Factory Reset, Backup restore)
  bool attached = true;     // plugged in: powered and on the line
  std::optional<sim::Scheduler::EventId> watchdog;  // the Bus Watchdog's expiry, while armed
  // Fault injection (docs/faults.md).
  bool silent_until_reboot = false;  // hears nothing but a Reboot until it reboots
  SimTime deaf_until{};              // busy writing EEPROM (eeprom_busy)
  // The current packet's servo faults, set by Bus::hear.
  bool deaf = false;    // does not hear it
  bool mute = false;    // executes it but does not answer
  SimDuration slow{0};  // extra processing time
};

// A reply scheduled for delivery. A collision marks it cancelled: the event still runs (the servo
// still applies deferred effects), but the bytes are not delivered.
struct Bus::Outgoing {
  bool cancelled = false;
};

namespace {

// One device's part of a Sync/Bulk Read, in request order.
struct ReadSlot {
  std::uint8_t id;
  std::uint16_t address;
  std::uint16_t length;
};

// Packets sent at the same moment by servos that share an ID: the line idles high and a 0 bit
// wins, so the client receives the bitwise AND of them (docs/bus.md "Collisions").
std::vector<std::uint8_t> collide(const std::vector<std::vector<std::uint8_t>>& packets) {
  std::vector<std::uint8_t> out;
  for (const auto& p : packets) {
    if (out.size() < p.size()) {
      out.resize(p.size(), 0xFF);
    }
    for (std::size_t i = 0; i < p.size(); ++i) {
      out[i] &= p[i];
    }
  }
  return out;
}

bool is_group_instruction(std::uint8_t code) {
  using wire::InstructionCode;
  for (const auto group :
       {InstructionCode::SyncRead, InstructionCode::SyncWrite, InstructionCode::FastSyncRead,
        InstructionCode::BulkRead, InstructionCode::BulkWrite, InstructionCode::FastBulkRead}) {
    if (code == wire::to_byte(group)) {
      return true;
    }
  }
  return false;
}

template <class T>
constexpr bool kIsGroupRead =
    std::is_same_v<T, wire::SyncRead> || std::is_same_v<T, wire::FastSyncRead> ||
    std::is_same_v<T, wire::BulkRead> || std::is_same_v<T, wire::FastBulkRead>;

template <class T>
constexpr bool kIsGroupWrite =
    std::is_same_v<T, wire::SyncWrite> || std::is_same_v<T, wire::BulkWrite>;

}  // namespace

Bus::Bus(sim::Scheduler& scheduler, ByteLink& link) : scheduler_(scheduler), link_(link) {}

Bus::~Bus() {
  if (injector_ != nullptr) {
    injector_->unsubscribe(fault_subscription_);
  }
}

SimDuration Bus::line_time(std::size_t bytes, std::uint32_t bps) const {
  return timing_ == ReplyTiming::Modelled ? wire_time(bytes, bps) : SimDuration{0};
}

// "For an instruction whose bytes arrived at t: line_end = t + wire(instruction)" (DESIGN.md).
// A packet written in pieces cannot end before its last piece arrived plus one byte time. The
// bytes of one write are stamped back to back (receive), so they take the first branch.
SimTime Bus::line_end(const wire::Frame& frame, std::uint32_t bps) const {
  const std::size_t size = frame.raw.size();
  if (frame.last_byte_at <= frame.first_byte_at + line_time(size - 1, bps)) {
    return frame.first_byte_at + line_time(size, bps);
  }
  return frame.last_byte_at + line_time(1, bps);
}

SimDuration Bus::turnaround(const Reply& reply) const {
  if (timing_ == ReplyTiming::Immediate) {
    return reply.station->slow;  // an injected delay shows in every timing mode
  }
  return reply.response.processing + reply.station->servo->return_delay() + reply.station->slow;
}

model::Servo& Bus::add_servo(std::unique_ptr<model::Servo> servo) {
  servos_.push_back(std::move(servo));
  stations_.push_back(std::make_unique<Station>());
  stations_.back()->servo = servos_.back().get();
  return *servos_.back();
}

bool Bus::booting(const model::Servo& servo) const {
  const Station* s = station_of(servo);
  return s != nullptr && scheduler_.now() < s->booting_until;
}

Bus::Station* Bus::station_of(const model::Servo& servo) const {
  for (const auto& s : stations_) {
    if (s->servo == &servo) {
      return s.get();
    }
  }
  return nullptr;
}

bool Bus::attached(const model::Servo& servo) const {
  const Station* s = station_of(servo);
  return s != nullptr && s->attached;
}

void Bus::detach(model::Servo& servo) {
  Station* s = station_of(servo);
  if (s == nullptr || !s->attached) {
    return;
  }
  // Unplugged: no power and no line. The motor gives no torque; the servo hears nothing.
  servo.advance_to(scheduler_.now());
  s->attached = false;
  if (s->watchdog) {
    scheduler_.cancel(*s->watchdog);
    s->watchdog.reset();
  }
  if (const auto torque = servo.spec().index_of("torque_enable")) {
    servo.table().set(*torque, 0);
  }
  servo.motion().wake();
}

void Bus::power_on(model::Servo& servo) {
  Station* s = station_of(servo);
  if (s == nullptr) {
    return;
  }
  // Powering on is a reboot: RAM back to its initial values, silent while it boots.
  servo.advance_to(scheduler_.now());
  s->attached = true;
  if (s->watchdog) {
    scheduler_.cancel(*s->watchdog);
    s->watchdog.reset();
  }
  servo.reboot();
  s->silent_until_reboot = false;
  s->deaf_until = {};
  s->booting_until = scheduler_.now() + std::chrono::milliseconds(servo.spec().timing.boot_ms);
}

void Bus::set_faults(faults::Injector* injector, std::string port) {
  if (injector_ != nullptr) {
    injector_->unsubscribe(fault_subscription_);
  }
  injector_ = injector;
  port_ = std::move(port);
  if (injector_ != nullptr) {
    fault_subscription_ = injector_->subscribe([this] { refresh_faults(); });
  }
  forget_servo_faults();
  refresh_faults();
}

void Bus::refresh_faults() {
  if (fault_window_) {
    scheduler_.cancel(*fault_window_);
    fault_window_.reset();
  }
  const SimTime now = scheduler_.now();
  catch_up(now);
  apply_hardware_faults(now);
  if (injector_ == nullptr) {
    return;
  }
  if (const auto next = injector_->next_state_change(now)) {
    fault_window_ = scheduler_.schedule_at(*next, [this] {
      fault_window_.reset();
      refresh_faults();
    });
  }
}

void Bus::apply_hardware_faults(SimTime now) {
  for (const auto& s : stations_) {
    const model::FaultSet faults =
        injector_ != nullptr ? injector_->hardware_faults(port_, s->servo->id(), now) : 0;
    if (faults != s->servo->motion().injected()) {
      s->servo->advance_to(now);
      s->servo->motion().set_injected(faults);
    }
  }
}

void Bus::receive(std::span<const std::uint8_t> bytes, SimTime at, std::uint32_t client_bps) {
  stats_.bytes_in += bytes.size();
  drop_pending_replies();
  // Each protocol's framer hears the line when a servo speaks that protocol (mixed buses). The
  // bytes of one write follow each other on the line, a byte time apart.
  std::vector<SimTime> times(bytes.size());
  for (std::size_t i = 0; i < times.size(); ++i) {
    times[i] = at + line_time(i, client_bps);
  }
  // Both framers' events go in the order their first bytes were on the line (the in-write
  // collision rule depends on it): by position in this write, negative when the bytes came in an
  // earlier one.
  std::vector<std::pair<std::int64_t, wire::FramerEvent>> heard;
  for (wire::Framer* framer : {&v1_framer_, &v2_framer_}) {
    const wire::Protocol protocol = framer->format().protocol;
    if (std::none_of(stations_.begin(), stations_.end(),
                     [&](const auto& s) { return s->servo->protocol() == protocol; })) {
      continue;
    }
    const auto base = static_cast<std::int64_t>(framer->fed());
    std::vector<wire::FramerEvent> events;
    framer->feed(bytes, times, events);
    for (auto& event : events) {
      heard.emplace_back(static_cast<std::int64_t>(wire::offset_of(event)) - base,
                         std::move(event));
    }
  }
  std::stable_sort(heard.begin(), heard.end(),
                   [](const auto& a, const auto& b) { return a.first < b.first; });
  std::vector<wire::FramerEvent> events;
  events.reserve(heard.size());
  for (auto& [position, event] : heard) {
    events.push_back(std::move(event));
  }
  handle(events, client_bps);
  schedule_expiry(client_bps);
}

// Collision policy (docs/bus.md): bytes from the client while replies are still due would garble
// them on a real half-duplex line. The pending replies are dropped; their servos still apply what
// the instruction changed. The new bytes are heard normally.
void Bus::drop_pending_replies() {
  if (outgoing_.empty()) {
    return;
  }
  ++stats_.collisions;
  for (const auto& o : outgoing_) {
    o->cancelled = true;
  }
  outgoing_.clear();
}

// A partial packet is dropped when the line stays quiet past the inter-byte timeout; an event at
// the framers' deadline makes that happen (and be counted) without waiting for more bytes.
void Bus::schedule_expiry(std::uint32_t client_bps) {
  if (expiry_) {
    scheduler_.cancel(*expiry_);
    expiry_.reset();
  }
  std::optional<SimTime> deadline;
  for (const wire::Framer* f : {&v1_framer_, &v2_framer_}) {
    if (const auto d = f->deadline(); d && (!deadline || *d < *deadline)) {
      deadline = d;
    }
  }
  if (!deadline) {
    return;
  }
  expiry_ = scheduler_.schedule_at(*deadline, [this, client_bps] {
    expiry_.reset();
    std::vector<wire::FramerEvent> events;
    v1_framer_.expire(scheduler_.now(), events);
    v2_framer_.expire(scheduler_.now(), events);
    handle(events, client_bps);
    schedule_expiry(client_bps);
  });
}

void Bus::catch_up(SimTime now) {
  for (const auto& servo : servos_) {
    servo->advance_to(now);
  }
  // hardware_error rules follow a servo's ID, which an instruction may have changed.
  if (injector_ != nullptr && !injector_->rules().empty()) {
    apply_hardware_faults(now);
  }
}

void Bus::handle(const std::vector<wire::FramerEvent>& events, std::uint32_t client_bps) {
  // Servos move between packets: each sees the instruction in the state it has reached.
  if (!events.empty()) {
    catch_up(scheduler_.now());
  }
  for (const wire::FramerEvent& event : events) {
    const auto* failure = std::get_if<wire::FramingError>(&event);
    // A packet written right behind another (in one write) is on the line while the replies to
    // the first are due: the same collision as a packet sent without waiting.
    if (failure == nullptr || failure->kind == wire::FramingErrorKind::BadCheck) {
      drop_pending_replies();
    }
    if (observer_.heard &&
        (failure == nullptr || failure->kind != wire::FramingErrorKind::Garbage)) {
      observer_.heard(event);
    }
    if (const auto* frame = std::get_if<wire::Frame>(&event)) {
      ++stats_.frames;
      on_frame(*frame, client_bps);
      continue;
    }
    const auto& error = std::get<wire::FramingError>(event);
    switch (error.kind) {
      case wire::FramingErrorKind::Garbage:
        stats_.garbage_bytes += error.bytes;
        break;
      case wire::FramingErrorKind::BadCheck:
        ++stats_.bad_checks;
        on_bad_check(error, error.at + line_time(error.bytes, client_bps), client_bps);
        break;
      case wire::FramingErrorKind::ImpossibleLength:
        ++stats_.impossible_lengths;
        break;
      case wire::FramingErrorKind::Truncated:
        ++stats_.truncated;
        break;
    }
  }
}

void Bus::rearm_watchdogs(wire::Protocol protocol, std::uint32_t client_bps, SimTime now) {
  // "The communication is defined as all the Instruction Packet in the DYNAMIXEL Protocol": every
  // packet a servo hears restarts its Bus Watchdog (includes/control_table_buswatchdog.md).
  for (Station* s : listeners(protocol, client_bps, now)) {
    if (s->watchdog) {
      scheduler_.cancel(*s->watchdog);
      s->watchdog.reset();
    }
    if (const auto period = s->servo->bus_watchdog_period()) {
      s->watchdog = scheduler_.schedule_at(now + *period, [s, expiry = now + *period] {
        s->watchdog.reset();
        s->servo->advance_to(expiry);
        if (s->servo->bus_watchdog_period()) {
          s->servo->expire_bus_watchdog();
        }
      });
    }
  }
}

std::vector<Bus::Station*> Bus::listeners(wire::Protocol protocol, std::uint32_t client_bps,
                                          SimTime now) {
  std::vector<Station*> out;
  for (const auto& s : stations_) {
    if (s->attached && s->servo->protocol() == protocol &&
        baud_matches(client_bps, s->servo->baud_bps()) && now >= s->booting_until &&
        now >= s->deaf_until && !s->deaf) {
      out.push_back(s.get());
    }
  }
  return out;
}

std::vector<Bus::Station*> Bus::addressed(const std::vector<Station*>& listening,
                                          std::uint8_t id) const {
  std::vector<Station*> out;
  for (Station* s : listening) {
    if (s->servo->id() == id) {
      out.push_back(s);
    }
  }
  return out;
}

void Bus::on_frame(const wire::Frame& frame, std::uint32_t client_bps) {
  const SimTime end = line_end(frame, client_bps);
  auto decoded = wire::decode_instruction(frame);
  const auto* decoded_packet = std::get_if<wire::InstructionPacket>(&decoded);
  current_ = {frame.instruction, decoded_packet};
  if (injector_ != nullptr) {
    forget_servo_faults();
    // The servos a packet is for: its ID, the IDs a Sync/Bulk instruction lists, or every servo
    // listening to a broadcast.
    std::vector<std::uint8_t> ids;
    if (decoded_packet != nullptr && is_group_instruction(frame.instruction)) {
      ids = faults::listed_ids(*decoded_packet);
    } else if (frame.id == wire::kBroadcastId) {
      for (const Station* s : listeners(frame.protocol, client_bps, end)) {
        ids.push_back(s->servo->id());
      }
    } else {
      ids.push_back(frame.id);
    }
    const faults::InstructionEffects effects = injector_->instruction(facts(std::move(ids), end));
    stats_.faults_injected += effects.any() ? 1 : 0;
    if (effects.echo) {
      send_at(frame.raw, end, frame.protocol, {}, false);
    }
    if (!effects.noise.empty()) {
      send_at(effects.noise, end, frame.protocol, {}, false);
    }
    if (effects.corrupt) {
      // The servos hear the packet with a broken check and answer as they would.
      current_.packet = nullptr;
      on_bad_check({wire::FramingErrorKind::BadCheck, frame.protocol, frame.raw.size(), frame.id,
                    frame.instruction, frame.first_byte_at},
                   end, client_bps);
      return;
    }
    hear(frame.protocol, frame.id, client_bps, end);
  }
  if (const auto* error = std::get_if<wire::DecodeError>(&decoded)) {
    ++stats_.decode_errors;
    // Group instructions are only heard from 0xFE and never answered there; a malformed one is
    // ignored like a well-formed one sent to a single ID.
    if (frame.id == wire::kBroadcastId || is_group_instruction(frame.instruction)) {
      return;
    }
    std::vector<Reply> replies;
    for (Station* s : addressed(listeners(frame.protocol, client_bps, end), frame.id)) {
      model::ServoResponse r = s->servo->refuse(*error, false);
      if (r.reply) {
        replies.push_back({s, r, status_bytes(*s, r)});
      }
    }
    answer({replies}, end);
    return;
  }
  const auto& packet = std::get<wire::InstructionPacket>(decoded);
  std::visit(
      [&](const auto& instruction) {
        using T = std::decay_t<decltype(instruction)>;
        if constexpr (kIsGroupRead<T>) {
          group_read(packet, end, client_bps);
        } else if constexpr (kIsGroupWrite<T>) {
          group_write(packet, end, client_bps);
        } else {
          single(packet, end, client_bps);
        }
      },
      packet.instruction);
  rearm_watchdogs(frame.protocol, client_bps, end);
}

void Bus::forget_servo_faults() {
  for (const auto& s : stations_) {
    s->deaf = false;
    s->mute = false;
    s->slow = SimDuration{0};
  }
}

faults::PacketFacts Bus::facts(std::vector<std::uint8_t> ids, SimTime at) const {
  faults::PacketFacts f{port_, current_.instruction, std::move(ids), std::nullopt, at};
  if (current_.packet != nullptr) {
    f.span = faults::span_of(*current_.packet,
                             f.ids.size() == 1 ? std::optional(f.ids.front()) : std::nullopt);
  }
  return f;
}

void Bus::hear(wire::Protocol protocol, std::uint8_t packet_id, std::uint32_t client_bps,
               SimTime end) {
  const bool broadcast = packet_id == wire::kBroadcastId;
  const std::vector<std::uint8_t> listed = current_.packet != nullptr
                                               ? faults::listed_ids(*current_.packet)
                                               : std::vector<std::uint8_t>{};
  for (Station* s : listeners(protocol, client_bps, end)) {
    const std::uint8_t id = s->servo->id();
    const bool for_it =
        broadcast ? listed.empty() || std::find(listed.begin(), listed.end(), id) != listed.end()
                  : id == packet_id || s->servo->secondary_id() == packet_id;
    if (!for_it) {
      continue;
    }
    const faults::ServoEffects effects = injector_->servo(facts({id}, end));
    stats_.faults_injected += effects.any() ? 1 : 0;
    s->silent_until_reboot = s->silent_until_reboot || effects.silence_until_reboot;
    s->slow = effects.slow;
    if (s->silent_until_reboot) {
      // Its firmware still reacts to a Reboot sent to its own ID, without answering.
      const bool reboot = current_.instruction == wire::to_byte(wire::InstructionCode::Reboot) &&
                          id == packet_id && current_.packet != nullptr;
      (reboot ? s->mute : s->deaf) = true;
    }
    s->deaf = s->deaf || effects.silence;
  }
}

void Bus::after_write(Station& station, std::uint16_t address, std::span<const std::uint8_t> data,
                      SimTime end) {
  if (injector_ == nullptr) {
    return;
  }
  // EEPROM bytes that now hold what was written (a refused write leaves them as they were).
  const model::ControlTable& table = station.servo->table();
  std::size_t written = 0;
  for (std::size_t i = 0; i < data.size(); ++i) {
    const std::size_t a = address + i;
    written += a < table.bytes().size() && table.touches_eeprom(static_cast<std::uint16_t>(a), 1) &&
                       table.bytes()[a] == data[i]
                   ? 1
                   : 0;
  }
  if (written == 0) {
    return;
  }
  const SimDuration busy = injector_->eeprom_write(facts({station.servo->id()}, end), written);
  if (busy.count() > 0) {
    ++stats_.faults_injected;
    station.deaf_until = std::max(station.deaf_until, end + busy);
  }
}

faults::ReplyEffects Bus::mangle(std::vector<std::uint8_t> ids, std::vector<std::uint8_t>& bytes,
                                 wire::Protocol protocol) {
  if (injector_ == nullptr) {
    return {};
  }
  const faults::ReplyEffects effects =
      injector_->reply(facts(std::move(ids), scheduler_.now()), bytes, protocol);
  stats_.faults_injected += effects.any ? 1 : 0;
  return effects;
}

void Bus::on_bad_check(const wire::FramingError& error, SimTime end, std::uint32_t client_bps) {
  // A servo answers a damaged packet sent to its ID with CRC Error (2.0) or the Checksum Error
  // bit (1.0); the ID is unverified, so whoever has that ID answers. Broadcast: silence.
  if (!error.id || *error.id == wire::kBroadcastId) {
    return;
  }
  current_ = {error.instruction.value_or(0), nullptr};
  if (injector_ != nullptr) {
    forget_servo_faults();
    hear(error.protocol, *error.id, client_bps, end);
  }
  std::vector<Reply> replies;
  for (Station* s : addressed(listeners(error.protocol, client_bps, end), *error.id)) {
    model::ServoResponse r = s->servo->bad_check(error.instruction);
    if (r.reply) {
      replies.push_back({s, r, status_bytes(*s, r)});
    }
  }
  answer({replies}, end);
}

void Bus::single(const wire::InstructionPacket& packet, SimTime end, std::uint32_t client_bps) {
  const bool broadcast = packet.id == wire::kBroadcastId;
  std::vector<std::pair<Station*, model::Addressing>> targets;
  for (Station* s : listeners(packet.protocol, client_bps, end)) {
    if (broadcast) {
      targets.emplace_back(s, model::Addressing::Broadcast);
    } else if (s->servo->id() == packet.id) {
      targets.emplace_back(s, model::Addressing::Unicast);
    } else if (s->servo->secondary_id() == packet.id) {
      // The ID takes priority, but the group of that Secondary ID executes too, silently.
      targets.emplace_back(s, model::Addressing::Secondary);
    }
  }
  // Broadcast Ping: every servo answers, in ascending ID order (protocol2.md "Ping" Example 2).
  std::stable_sort(targets.begin(), targets.end(), [](const auto& a, const auto& b) {
    return a.first->servo->id() < b.first->servo->id();
  });
  std::vector<Reply> replies;
  const auto* write = std::get_if<wire::Write>(&packet.instruction);
  for (const auto& [s, addressing] : targets) {
    model::ServoResponse r = s->servo->execute(packet, addressing);
    if (write != nullptr) {
      after_write(*s, write->address, write->data, end);
    }
    if (r.reply && !s->mute) {
      replies.push_back({s, r, status_bytes(*s, r)});
    } else {
      settle(*s, r.reboot_after, end);
    }
  }
  // Protocol 2.0 chains broadcast Ping replies, one slot per ID (servos sharing an ID collide in
  // theirs); Protocol 1.0 defines no order, so 1.0 servos answer a broadcast Ping at once and
  // collide when there are several. A unicast instruction has one slot (docs/bus.md).
  std::vector<Slot> slots;
  for (Reply& r : replies) {
    const bool new_slot =
        slots.empty() || (broadcast && packet.protocol == wire::Protocol::V2 &&
                          slots.back().front().station->servo->id() != r.station->servo->id());
    if (new_slot) {
      slots.emplace_back();
    }
    slots.back().push_back(std::move(r));
  }
  answer(slots, end);
}

void Bus::group_read(const wire::InstructionPacket& packet, SimTime end, std::uint32_t client_bps) {
  if (packet.id != wire::kBroadcastId) {
    return;  // "The Packet ID must be 0xFE": a servo ignores a Sync/Bulk Read sent to its own ID
  }
  bool fast = false;
  bool v1_bulk = false;
  std::vector<ReadSlot> slots;
  // protocol1.md (Bulk Read): "If an identical ID is designated multiple times, only the first
  // designated parameter will be processed." A servo handles a packet once, so Sync Read too.
  auto add_slot = [&](const ReadSlot& slot) {
    if (std::none_of(slots.begin(), slots.end(),
                     [&](const ReadSlot& s) { return s.id == slot.id; })) {
      slots.push_back(slot);
    }
  };
  std::visit(
      [&](const auto& ins) {
        using T = std::decay_t<decltype(ins)>;
        if constexpr (std::is_base_of_v<wire::SyncRead, T>) {
          fast = std::is_same_v<T, wire::FastSyncRead>;
          for (const std::uint8_t id : ins.ids) {
            add_slot({id, ins.address, ins.length});
          }
        } else if constexpr (std::is_base_of_v<wire::BulkRead, T>) {
          fast = std::is_same_v<T, wire::FastBulkRead>;
          v1_bulk = packet.protocol == wire::Protocol::V1;
          for (const wire::BulkReadTarget& t : ins.targets) {
            add_slot({t.id, t.address, t.length});
          }
        }
      },
      packet.instruction);
  // A Fast reply announces every listed device's block in one 16-bit LENGTH: a request for more
  // than that can announce has no reply any device could send, so it goes unanswered.
  if (fast) {
    std::size_t length = 1;  // the instruction byte
    for (const ReadSlot& slot : slots) {
      length += 4 + std::size_t{slot.length};  // error, ID, data, CRC
    }
    if (length > std::numeric_limits<std::uint16_t>::max()) {
      return;
    }
  }

  const std::vector<Station*> listening = listeners(packet.protocol, client_bps, end);
  std::vector<Slot> answered;  // one per listed device that answers, in list order
  for (const ReadSlot& slot : slots) {
    std::vector<Station*> matches = addressed(listening, slot.id);
    std::erase_if(matches, [&](const Station* s) {
      return !s->servo->replies_to(true) || (fast && !s->servo->supports_fast_read()) ||
             (v1_bulk && !s->servo->supports_v1_bulk_read());
    });
    // Each device waits for the status of the one before it (protocol1.md "Bulk Read"): when a
    // listed device does not answer, the ones after it wait in vain and stay silent.
    if (matches.empty()) {
      break;
    }
    Slot& out = answered.emplace_back();
    for (Station* s : matches) {  // servos sharing the ID all answer, and collide
      model::ServoResponse r = s->servo->read_part(slot.address, slot.length);
      if (fast) {
        r.params.resize(slot.length, 0);  // a failed read still fills its block (docs/bus.md)
      }
      std::vector<std::uint8_t> bytes = fast ? std::vector<std::uint8_t>{} : status_bytes(*s, r);
      out.push_back({s, std::move(r), std::move(bytes)});
    }
  }
  if (answered.empty()) {
    return;
  }
  if (!fast) {
    answer(answered, end);
    return;
  }
  // Fast Sync/Bulk Read: one packet from ID 0xFE, charged one processing time and one Return
  // Delay Time (the first device's). If the chain broke, LENGTH still announces every listed
  // device and the packet stops after the last block sent: the client sees it cut short. Where
  // servos share an ID, each sends its own version of the packet at once: they collide.
  std::size_t versions = 0;
  for (const Slot& slot : answered) {
    versions = std::max(versions, slot.size());
    stats_.id_conflicts += slot.size() > 1 ? 1 : 0;
  }
  std::vector<std::vector<std::uint8_t>> packets;
  for (std::size_t v = 0; v < versions; ++v) {
    wire::FastReply reply;
    for (std::size_t i = 0; i < slots.size(); ++i) {
      if (i < answered.size()) {
        const Reply& r = answered[i][std::min(v, answered[i].size() - 1)];
        reply.blocks.push_back({r.response.error, slots[i].id, r.response.params});
      } else {
        reply.blocks.push_back({0, slots[i].id, std::vector<std::uint8_t>(slots[i].length, 0)});
      }
    }
    std::vector<std::uint8_t> bytes = wire::encode_fast_reply(reply);
    std::size_t sent = 8;  // header, ID, LENGTH, 0x55
    for (std::size_t i = 0; i < answered.size(); ++i) {
      sent += 4 + slots[i].length;
    }
    bytes.resize(sent);
    packets.push_back(std::move(bytes));
  }
  const Reply& first = answered.front().front();
  std::vector<Settlement> settlements;
  std::vector<std::uint8_t> ids;
  for (const Slot& slot : answered) {
    for (const Reply& r : slot) {
      settlements.push_back({r.station, false});
      ids.push_back(r.station->servo->id());
    }
  }
  std::vector<std::uint8_t> bytes = collide(packets);
  const std::size_t sent_size = bytes.size();
  const faults::ReplyEffects effects = mangle(std::move(ids), bytes, wire::Protocol::V2);
  const SimTime start = end + turnaround(first) + effects.delay;
  const SimTime delivered = start + line_time(effects.dropped ? sent_size : bytes.size(),
                                              first.station->servo->baud_bps());
  send_at(std::move(bytes), delivered, wire::Protocol::V2, std::move(settlements));
}

void Bus::group_write(const wire::InstructionPacket& packet, SimTime end,
                      std::uint32_t client_bps) {
  if (packet.id != wire::kBroadcastId) {
    return;  // "The Packet ID must be 0xFE"
  }
  const std::vector<Station*> listening = listeners(packet.protocol, client_bps, end);
  auto write_to = [&](std::uint8_t id, std::uint16_t address,
                      const std::vector<std::uint8_t>& data) {
    for (Station* s : addressed(listening, id)) {
      s->servo->write_part(address, data);
      after_write(*s, address, data, end);
      settle(*s, false, end);
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
      packet.instruction);
}

wire::Protocol Bus::status_protocol(const Station& station) {
  return station.servo->protocol().value_or(wire::Protocol::V2);
}

std::vector<std::uint8_t> Bus::status_bytes(const Station& station,
                                            const model::ServoResponse& response) const {
  return wire::encode_status(
      {status_protocol(station), station.servo->id(), response.error, response.params});
}

void Bus::answer(const std::vector<Slot>& slots, SimTime start_after) {
  // A reply starts after the instruction (or the previous slot) ends, plus the servo's own
  // processing time and Return Delay Time, and reaches the client when its last byte would.
  SimTime after = start_after;
  for (const Slot& slot : slots) {
    if (slot.empty()) {
      continue;
    }
    SimTime slot_end = after;
    std::vector<std::vector<std::uint8_t>> packets;
    std::vector<Settlement> settlements;
    for (const Reply& r : slot) {
      std::vector<std::uint8_t> bytes = r.bytes;
      const faults::ReplyEffects effects =
          mangle({r.station->servo->id()}, bytes, status_protocol(*r.station));
      const SimTime start = after + turnaround(r) + effects.delay;
      // A dropped status still took its time on the line: the chain after it keeps its timing.
      const std::size_t on_line = effects.dropped ? r.bytes.size() : bytes.size();
      slot_end = std::max(slot_end, start + line_time(on_line, r.station->servo->baud_bps()));
      if (!bytes.empty()) {
        packets.push_back(std::move(bytes));
      }
      settlements.push_back({r.station, r.response.reboot_after});
    }
    if (slot.size() > 1) {
      ++stats_.id_conflicts;
    }
    send_at(collide(packets), slot_end, status_protocol(*slot.front().station),
            std::move(settlements));
    after = slot_end;
  }
}

void Bus::send_at(std::vector<std::uint8_t> bytes, SimTime at, wire::Protocol protocol,
                  std::vector<Settlement> settlements, bool is_reply) {
  auto outgoing = std::make_shared<Outgoing>();
  outgoing_.push_back(outgoing);
  scheduler_.schedule_at(at, [this, outgoing, protocol, is_reply, bytes = std::move(bytes),
                              settlements = std::move(settlements)] {
    std::erase(outgoing_, outgoing);
    if (!outgoing->cancelled && !bytes.empty()) {
      if (link_.deliver(bytes, scheduler_.now())) {
        stats_.replies += is_reply ? 1 : 0;
      } else {
        ++stats_.unread_drops;
      }
      if (observer_.sent) {
        observer_.sent(bytes, scheduler_.now(), protocol);
      }
    }
    // ID, Baud Rate, Protocol Type and Return Delay Time change after the status went out.
    for (const Settlement& s : settlements) {
      settle(*s.station, s.reboot, scheduler_.now());
    }
  });
}

void Bus::settle(Station& station, bool reboot, SimTime at) {
  station.servo->advance_to(at);
  station.servo->commit_deferred();
  if (reboot) {
    station.servo->reboot();
    station.silent_until_reboot = false;
    station.booting_until = at + std::chrono::milliseconds(station.servo->spec().timing.boot_ms);
  }
}

}  // namespace dxlemu::bus
