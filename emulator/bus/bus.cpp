// The bus's own state and the way in: servos joining, unplugged and powered on, the client's
// bytes framed, and the Bus Watchdog. Who hears a packet is in bus_hearing.cpp, what servos do
// with it in bus_instructions.cpp, and the replies' timing in bus_replies.cpp.
#include "bus/bus.hpp"

#include <algorithm>

#include "bus/bus_node.hpp"

namespace dxlemu::bus {

using sim::SimTime;

Bus::Bus(sim::Scheduler& scheduler, ByteLink& link) : scheduler_(scheduler), link_(link) {
  framers_.reserve(wire::kProtocolCount);
  for (const wire::ProtocolTraits& row : wire::kProtocolTable) {
    framers_.emplace_back(row.protocol);
  }
}

Bus::~Bus() = default;

model::Servo& Bus::add_servo(std::unique_ptr<model::Servo> servo) {
  servos_.push_back(std::move(servo));
  nodes_.push_back(std::make_unique<Node>());
  nodes_.back()->servo = servos_.back().get();
  nodes_.back()->index = servos_.size() - 1;
  return *servos_.back();
}

bool Bus::booting(const model::Servo& servo) const {
  const Node* s = node_of(servo);
  return s != nullptr && scheduler_.now() < s->booting_until;
}

Bus::Node* Bus::node_of(const model::Servo& servo) const {
  for (const auto& s : nodes_) {
    if (s->servo == &servo) {
      return s.get();
    }
  }
  return nullptr;
}

bool Bus::attached(const model::Servo& servo) const {
  const Node* s = node_of(servo);
  return s != nullptr && s->attached;
}

void Bus::detach(model::Servo& servo) {
  Node* s = node_of(servo);
  if (s == nullptr || !s->attached) {
    return;
  }
  // Unplugged: no power and no line. The motor gives no torque; the servo hears nothing.
  servo.advance_to(scheduler_.now());
  s->attached = false;
  disarm_watchdog(*s);
  servo.power_off();
}

void Bus::power_on(model::Servo& servo) {
  Node* s = node_of(servo);
  if (s == nullptr) {
    return;
  }
  // Powering on is a reboot: RAM back to its initial values, silent while it boots.
  servo.advance_to(scheduler_.now());
  s->attached = true;
  disarm_watchdog(*s);
  restart(*s, scheduler_.now());
  if (faults_ != nullptr) {
    faults_->powered_on(s->index);
  }
}

model::ServoResponse Bus::instruct(model::Servo& servo, const wire::InstructionPacket& packet) {
  Node* s = node_of(servo);
  if (s == nullptr) {
    return {};
  }
  servo.advance_to(scheduler_.now());
  model::ServoResponse response = servo.execute(packet, model::Addressing::Unicast);
  settle(*s, response.reboot_after, scheduler_.now());
  return response;
}

BusStats Bus::stats() const {
  BusStats out = stats_;
  out.faults_injected = faults_ != nullptr ? faults_->injected() : 0;
  return out;
}

void Bus::receive(std::span<const std::uint8_t> bytes, SimTime at, std::uint32_t client_bps) {
  client_bps_ = client_bps;
  // An empty write puts nothing on the line: it garbles no reply still due.
  if (bytes.empty()) {
    return;
  }
  stats_.bytes_in += bytes.size();
  drop_pending_replies();
  // Each protocol's framer hears the line when a servo speaks that protocol (mixed DYNAMIXEL
  // buses; a port of FEETECH servos has only those, app/config/bus_config refuses a mix). The
  // bytes of one write follow each other on the line, a byte time apart.
  std::vector<SimTime> times(bytes.size());
  for (std::size_t i = 0; i < times.size(); ++i) {
    times[i] = at + line_time(i, client_bps_);
  }
  // The framers' events go in the order their first bytes were on the line (the in-write
  // collision rule depends on it): by position in this write, negative when the bytes came in an
  // earlier one.
  std::vector<std::pair<std::int64_t, wire::FramerEvent>> heard;
  for (wire::Framer& framer : framers_) {
    const wire::Protocol protocol = framer.format().protocol;
    if (std::none_of(nodes_.begin(), nodes_.end(),
                     [&](const auto& s) { return s->servo->protocol() == protocol; })) {
      continue;
    }
    const auto base = static_cast<std::int64_t>(framer.fed());
    std::vector<wire::FramerEvent> events;
    framer.set_line_rate(client_bps_);
    framer.feed(bytes, times, events);
    // Without modelled delays simulated time may stand still (manual timing): a frame that
    // ends at a silence ends with the write (docs/modbus.md "Timing").
    if (timing_ == ReplyTiming::Immediate) {
      framer.end_of_write(events);
    }
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
  handle(events);
  schedule_expiry();
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
void Bus::schedule_expiry() {
  if (expiry_) {
    scheduler_.cancel(*expiry_);
    expiry_.reset();
  }
  std::optional<SimTime> deadline;
  for (const wire::Framer& f : framers_) {
    if (const auto d = f.deadline(); d && (!deadline || *d < *deadline)) {
      deadline = d;
    }
  }
  if (!deadline) {
    return;
  }
  expiry_ = scheduler_.schedule_at(*deadline, [this] {
    expiry_.reset();
    std::vector<wire::FramerEvent> events;
    for (wire::Framer& framer : framers_) {
      framer.expire(scheduler_.now(), events);
    }
    // A packet found only when the partial one before it timed out is acted on now: its reply
    // is modelled from the expiry, not from when its bytes came (which would make it late by
    // the whole timeout). A frame that ends at a silence is found by the expiry itself, and
    // line_end() counts the silence.
    for (wire::FramerEvent& event : events) {
      auto* frame = std::get_if<wire::Frame>(&event);
      if (frame != nullptr &&
          wire::traits(frame->protocol).frame.delimiting != wire::Delimiting::Silence) {
        frame->last_byte_at = std::max(frame->last_byte_at, scheduler_.now());
      }
    }
    handle(events);
    schedule_expiry();
  });
}

void Bus::catch_up(SimTime now) {
  for (const auto& servo : servos_) {
    servo->advance_to(now);
  }
  if (faults_ != nullptr) {
    faults_->follow(now);
  }
}

void Bus::handle(const std::vector<wire::FramerEvent>& events) {
  // Servos move between packets: each sees the instruction in the state it has reached.
  if (!events.empty()) {
    catch_up(scheduler_.now());
  }
  for (const wire::FramerEvent& event : events) {
    const auto* failure = std::get_if<wire::FramingError>(&event);
    // A packet written right behind another (in one write) is on the line while the replies to
    // the first are due: the same collision as a packet sent without waiting. A frame that ends
    // at a silence (Modbus RTU) is never right behind another in one write, and is known only
    // once the silence after it has passed: what its bytes collided with was dropped when they
    // came (receive). The replies due then answer packets in those same bytes (a 2.0 status
    // to a packet the Modbus servos reject as a bad CRC) and stand.
    const wire::Protocol protocol =
        failure != nullptr ? failure->protocol : std::get<wire::Frame>(event).protocol;
    const bool after_silence = wire::traits(protocol).frame.delimiting == wire::Delimiting::Silence;
    if ((failure == nullptr || failure->kind == wire::FramingErrorKind::BadCheck) &&
        !after_silence) {
      drop_pending_replies();
    }
    if (observer_.heard &&
        (failure == nullptr || failure->kind != wire::FramingErrorKind::Garbage)) {
      observer_.heard(event);
    }
    if (const auto* frame = std::get_if<wire::Frame>(&event)) {
      ++stats_.frames;
      on_frame(*frame);
      continue;
    }
    switch (failure->kind) {
      case wire::FramingErrorKind::Garbage:
        stats_.garbage_bytes += failure->bytes;
        break;
      case wire::FramingErrorKind::BadCheck:
        ++stats_.bad_checks;
        on_bad_check(*failure);
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

void Bus::rearm_watchdogs(const Packet& packet) {
  // "The communication is defined as all the Instruction Packet in the DYNAMIXEL Protocol": every
  // packet a servo hears restarts its Bus Watchdog (includes/control_table_buswatchdog.md).
  const SimTime now = packet.heard.end;
  for (const Listener& l : packet.listening) {
    Node* s = l.node;
    disarm_watchdog(*s);
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

void Bus::disarm_watchdog(Node& node) {
  if (node.watchdog) {
    scheduler_.cancel(*node.watchdog);
    node.watchdog.reset();
  }
}

}  // namespace dxlemu::bus
