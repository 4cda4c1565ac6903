#include "app/daemon/emulator.hpp"

#include <boost/asio/post.hpp>
#include <boost/asio/signal_set.hpp>
#include <chrono>
#include <csignal>
#include <nlohmann/json.hpp>

#include "app/config/make_servo.hpp"
#include "app/daemon/bus_port_view.hpp"
#include "app/daemon/log.hpp"
#include "app/record/trace_record.hpp"
#include "bus/bus.hpp"
#include "bus/late_reply_guard.hpp"
#include "bus/usb_adapter_link.hpp"
#include "control/reply.hpp"
#include "control/scenario.hpp"
#include "io/atomic_file.hpp"
#include "io/pty_handover.hpp"
#include "io/pty_link.hpp"
#include "io/realtime_scheduling.hpp"
#include "physics/mjcf_world.hpp"

namespace dxlemu::app {
namespace {

// After a control API shutdown, how long replies still queued get to reach their clients.
constexpr std::chrono::milliseconds kShutdownFlush{100};
// How far the physics world may lag simulated time between reads (Emulator::world_).
constexpr std::chrono::milliseconds kPhysicsCatchUp{10};

// The USB serial adapter in front of `port`: its own settings, else the command line's. None
// under fast timing, whose replies come at once (docs/timing.md "USB adapter latency").
bus::UsbAdapter usb_adapter(const PortConfig& port, const RunOptions& options) {
  const int latency_ms = port.adapter_latency_ms.value_or(options.adapter_latency_ms);
  const std::string chip = port.adapter_chip.value_or(options.adapter_chip);
  if (latency_ms == 0 || options.timing == TimingMode::Fast) {
    return {};
  }
  return {std::chrono::milliseconds(latency_ms), adapter_packet_data(chip).value()};
}

}  // namespace

struct Emulator::Port {
  PortConfig config;
  std::unique_ptr<io::PtyLink> pty;
  /// Between the bus and the PTY under realtime and fast timing: measures how late replies go
  /// out and drops those the client no longer waits for.
  std::unique_ptr<bus::LateReplyGuard> guard;
  std::unique_ptr<bus::UsbAdapterLink> adapter;  // between the bus and the PTY; null: none
  std::string adapter_chip;
  std::unique_ptr<bus::Bus> bus;
  std::unique_ptr<BusPortView> view;  // the bus as the control API sees it
};

Emulator::Emulator(const ModelLibrary& library, const BusConfig& config, const RunOptions& options)
    : options_(options),
      driver_(io_, scheduler_,
              options.timing == TimingMode::Manual ? io::Pace::Manual : io::Pace::WallClock),
      injector_(options.seed) {
  // What can be refused is checked before the first PTY opens, except the state's values, which
  // need the servos; a refusal then unwinds every port (links removed) before any readiness line.
  for (const PortConfig& port_config : config.ports) {
    for (const ServoConfig& servo : port_config.servos) {
      check_servo(servo, library);
    }
    if (const auto other = other_maker_servo(port_config, library)) {
      throw std::invalid_argument("port " + port_config.name + ": " +
                                  other_maker_reason(port_config, *other, library));
    }
  }
  // The world and its joints before any PTY: an MJCF that does not load, or names no such joint,
  // refuses the config.
  std::vector<model::JointMapping> joints;
  if (config.physics) {
    world_ = load_physics(*config.physics, options_.tick);
    for (std::size_t i = 0; i < config.physics->joints.size(); ++i) {
      joints.push_back(joint_mapping(*config.physics, i, world_->world()));
    }
    log(LogLevel::Info, "physics: " + physics::physics_engine() + " stepping " +
                            config.physics->mjcf.string() + ", " +
                            std::to_string(world_->substeps()) + " step(s) per motion tick");
  }
  const BusState state = options_.state ? read_state(*options_.state) : BusState{};
  if (options_.trace) {
    trace_.open(*options_.trace, std::ios::trunc);
    if (!trace_) {
      throw ConfigError(options_.trace->string(), "", "cannot be created (--trace)");
    }
  }
  if (options_.pcap) {
    pcap_file_.open(*options_.pcap, std::ios::binary | std::ios::trunc);
    if (!pcap_file_) {
      throw ConfigError(options_.pcap->string(), "", "cannot be created (--pcap)");
    }
    // The one wall-clock read of the capture: simulated time started with the driver, just now.
    const auto start = std::chrono::duration_cast<std::chrono::microseconds>(
        std::chrono::system_clock::now().time_since_epoch());
    pcap_ = std::make_unique<PcapWriter>(pcap_file_, start);
  }
  if (options_.realtime_priority) {
    const io::RealtimeScheduling granted =
        io::request_realtime_scheduling(*options_.realtime_priority);
    log(granted.fifo && granted.locked ? LogLevel::Info : LogLevel::Warn,
        "--realtime-priority: " + granted.message);
  }
  if (options_.timing == TimingMode::Realtime) {
    // Measured only when not given: value_or would run the measurement (~30 ms) either way.
    handover_ = options_.pty_handover ? *options_.pty_handover : io::measure_pty_handover();
    log(LogLevel::Info,
        "PTY hand-over (both ways) " +
            std::to_string(
                std::chrono::duration_cast<std::chrono::microseconds>(handover_).count()) +
            " us: the client's bytes count as written that much earlier");
  }
  for (const PortConfig& port_config : config.ports) {
    auto port = std::make_unique<Port>();
    port->config = port_config;
    port->pty = std::make_unique<io::PtyLink>(io_, port_config.link);
    bus::ByteLink* link = port->pty.get();
    if (options_.timing != TimingMode::Manual) {
      // Under manual timing simulated time is not the wall clock's: nothing can be late.
      bus::LateReplyPolicy policy;
      policy.drop_after = options_.late_reply_limit;
      port->guard = std::make_unique<bus::LateReplyGuard>(
          *link, [this] { return driver_.wall_now(); }, policy,
          [name = port_config.name](const std::string& message) {
            log(LogLevel::Warn, name + ": " + message);
          });
      link = port->guard.get();
    }
    // The adapter before the guard: the guard measures when the adapter's USB packets go out.
    if (const bus::UsbAdapter usb = usb_adapter(port_config, options_);
        usb.latency > sim::SimDuration::zero()) {
      port->adapter = std::make_unique<bus::UsbAdapterLink>(scheduler_, *link, usb);
      port->adapter_chip = port_config.adapter_chip.value_or(options_.adapter_chip);
      link = port->adapter.get();
    } else if (options_.timing == TimingMode::Fast &&
               port_config.adapter_latency_ms.value_or(options_.adapter_latency_ms) != 0) {
      log(LogLevel::Warn, port_config.name + ": no USB adapter latency under --timing fast");
    }
    port->bus = std::make_unique<bus::Bus>(scheduler_, *link);
    port->view = std::make_unique<BusPortView>(*port->bus, port->guard.get());
    if (options_.timing != TimingMode::Realtime) {
      port->bus->set_reply_timing(bus::ReplyTiming::Immediate);
    }
    for (const ServoConfig& servo : port_config.servos) {
      port->bus->add_servo(make_servo(library, servo, options.tick));
    }
    // One observer feeds the trace file, the capture and the control API's trace subscribers,
    // so all can be on at once; each record is built once, only when someone wants it.
    const std::string name = port_config.name;
    const std::size_t index = ports_.size();
    port->bus->set_observer({[this, name, index](const wire::FramerEvent& event) {
                               if (trace_.is_open() || !subscribers_.empty()) {
                                 trace(name, heard_record(name, event));
                               }
                               if (pcap_) {
                                 pcap_->heard(index, event);
                               }
                             },
                             [this, name, index](std::span<const std::uint8_t> bytes,
                                                 sim::SimTime at, wire::Protocol p) {
                               if (trace_.is_open() || !subscribers_.empty()) {
                                 trace(name, sent_record(name, bytes, at, p));
                               }
                               if (pcap_) {
                                 pcap_->sent(index, bytes, at, p);
                               }
                             }});
    port->bus->set_faults(&injector_, port_config.name);
    ports_.push_back(std::move(port));
  }
  restore(state);
  if (config.physics) {
    for (std::size_t i = 0; i < joints.size(); ++i) {
      const JointConfig& j = config.physics->joints[i];
      model::Servo* servo = nullptr;
      for (const auto& port : ports_) {
        for (const auto& s : port->bus->servos()) {
          if (servo == nullptr && port->config.name == j.port && s->id() == j.id) {
            servo = s.get();  // the first of that ID: a port may hold two (docs/bus.md)
          }
        }
      }
      servo->motion().couple(*world_, joints[i]);
    }
    physics_view_.emplace(control::PhysicsView{*world_, config.physics->mjcf, {}});
    for (const JointConfig& j : config.physics->joints) {
      physics_view_->coupled.push_back({j.joint, j.port, j.id});
    }
    schedule_physics_catch_up();
  }
  // EEPROM also changes in scheduled events (a reboot that restores a Control Table Backup).
  driver_.set_after_events([this] { finish_handler(); });
  api_ = std::make_unique<control::Api>(*this);
  control_ = std::make_unique<io::ControlServer>(
      io_, options_.control.value_or(default_control_path()),
      [this](std::string_view line, io::ControlSession& session) {
        driver_.catch_up();
        current_session_ = &session;
        std::string reply = api_->handle(line, session.id());
        current_session_ = nullptr;
        driver_.rearm();
        finish_handler();  // a set of an EEPROM item is kept like a bus write
        return reply;
      },
      io::ControlServer::Replies{control::oversize_line, control::internal_error_line});
  control_->on_close([this](io::ControlSession& session) { subscribers_.erase(session.id()); });
  if (options_.scenario) {
    // Its steps count from now, the start of simulated time.
    const std::string origin = options_.scenario->string();
    try {
      control::schedule_scenario(*this, control::load_scenario_file(*options_.scenario), origin);
    } catch (const control::ScenarioError& e) {
      throw ConfigError(origin, e.pointer(), e.what());
    }
  }
}

Emulator::~Emulator() = default;

void Emulator::trace(const std::string& port, const std::string& line) {
  if (trace_.is_open()) {
    trace_ << line << '\n';  // flushed when the handler is done (finish_handler)
  }
  if (subscribers_.empty()) {
    return;
  }
  // The same members after "event": a record is never empty, so `line` is "{...,...}".
  const std::string event = R"({"event":"trace",)" + line.substr(1);
  for (auto& [client, subscriber] : subscribers_) {
    if (subscriber.ports.empty() || std::find(subscriber.ports.begin(), subscriber.ports.end(),
                                              port) != subscriber.ports.end()) {
      subscriber.session->send(event);
    }
  }
}

void Emulator::subscribe_trace(std::uint64_t client, std::vector<std::string> ports) {
  // Only ever called while that client's request is handled.
  if (current_session_ != nullptr && current_session_->id() == client) {
    subscribers_[client] = {current_session_, std::move(ports)};
  }
}

void Emulator::unsubscribe_trace(std::uint64_t client) {
  subscribers_.erase(client);
}

void Emulator::schedule_in(sim::SimDuration delay, std::function<void()> action) {
  scheduler_.schedule_at(scheduler_.now() + delay, std::move(action));
}

void Emulator::schedule_physics_catch_up() {
  scheduler_.schedule_at(scheduler_.now() + kPhysicsCatchUp, [this] {
    world_->advance_to(scheduler_.now());
    schedule_physics_catch_up();
  });
}

void Emulator::warn(const std::string& message) {
  log(LogLevel::Warn, message);
}

std::vector<std::string> Emulator::port_names() const {
  std::vector<std::string> names;
  names.reserve(ports_.size());
  for (const auto& port : ports_) {
    names.push_back(port->config.name);
  }
  return names;
}

control::PortView* Emulator::port(std::string_view name) {
  for (const auto& p : ports_) {
    if (p->config.name == name) {
      return p->view.get();
    }
  }
  return nullptr;
}

nlohmann::json Emulator::port_info(std::string_view port) const {
  for (const auto& p : ports_) {
    if (p->config.name == port) {
      nlohmann::json info = {{"pty", p->pty->slave_path()}};
      if (p->config.link) {
        info["link"] = p->config.link->string();
      }
      info["adapter"] = {{"latency_ms", 0}};
      if (p->adapter) {
        const bus::UsbAdapter& usb = p->adapter->adapter();
        info["adapter"] = {
            {"latency_ms",
             std::chrono::duration_cast<std::chrono::milliseconds>(usb.latency).count()},
            {"chip", p->adapter_chip},
            {"packet_data_bytes", usb.packet_data},
            {"unread_drops", p->adapter->unread_drops()}};
      }
      return info;
    }
  }
  return nlohmann::json::object();
}

sim::SimTime Emulator::now() const {
  return scheduler_.now();
}

bool Emulator::manual_clock() const {
  return options_.timing == TimingMode::Manual;
}

void Emulator::step_clock(sim::SimDuration d) {
  scheduler_.advance_by(d);
}

void Emulator::request_shutdown() {
  log(LogLevel::Info, "stopping on the control API's shutdown");
  shutting_down_ = true;
  boost::asio::post(io_, [this] { io_.stop(); });
}

void Emulator::restore(const BusState& state) {
  for (const auto& port : ports_) {
    const auto it = state.find(port->config.name);
    const auto& servos = port->bus->servos();
    for (std::size_t i = 0; i < servos.size(); ++i) {
      model::Servo& servo = *servos[i];
      if (it != state.end() && i < it->second.size()) {
        const ServoState& saved = it->second[i];
        if (saved.model == servo.spec().name) {
          restore_state(servo.table(), saved, options_.state->string(),
                        "/ports/" + port->config.name + "/" + std::to_string(i));
        } else {
          log(LogLevel::Warn, options_.state->string() + ": " + port->config.name + " servo " +
                                  std::to_string(i) + " was a " + saved.model + ", now a " +
                                  servo.spec().name + ": it starts from its config");
        }
      }
      servo.commit_deferred();  // the ID, baud and protocol of the config and the state apply
    }
  }
  save_state_if_changed();
}

void Emulator::finish_handler() {
  // Once per handler rather than per line: a round trip writes two trace lines, and a reader
  // (tail -f) still sees each packet as soon as the daemon is done with it.
  if (trace_.is_open()) {
    trace_.flush();
  }
  save_state_if_changed();
  cpu_wait_.mark();  // the thread goes back to waiting for the next handler
}

void Emulator::save_state_if_changed() {
  if (!options_.state) {
    return;
  }
  // Called on every PTY read: while no EEPROM byte has changed since the last look, there is
  // nothing to compare.
  std::uint64_t changes = 0;
  for (const auto& port : ports_) {
    for (const auto& servo : port->bus->servos()) {
      changes += servo->table().eeprom_changes();
    }
  }
  if (checked_eeprom_changes_ == changes) {
    return;
  }
  // A byte may have changed and changed back: the images decide, as they always did.
  std::vector<std::vector<std::uint8_t>> images;
  for (const auto& port : ports_) {
    for (const auto& servo : port->bus->servos()) {
      images.push_back(eeprom_image(servo->table()));
    }
  }
  if (images == saved_eeprom_) {  // empty at first: the first call always writes
    checked_eeprom_changes_ = changes;
    return;
  }
  BusState state;
  for (const auto& port : ports_) {
    auto& list = state[port->config.name];
    for (const auto& servo : port->bus->servos()) {
      list.push_back(capture_state(servo->table()));
    }
  }
  io::write_file_atomically(*options_.state, state_to_text(state));
  saved_eeprom_ = std::move(images);
  checked_eeprom_changes_ = changes;
  log(LogLevel::Debug, "saved the EEPROM of every servo to " + options_.state->string());
}

void Emulator::run(std::ostream& out) {
  // Signals first: a script may send SIGTERM the moment it reads the readiness line.
  boost::asio::signal_set signals(io_, SIGINT, SIGTERM);
  signals.async_wait([this](const boost::system::error_code& ec, int signal) {
    if (!ec) {
      log(LogLevel::Info, std::string("stopping on ") + (signal == SIGINT ? "SIGINT" : "SIGTERM"));
      io_.stop();
    }
  });
  for (std::size_t index = 0; index < ports_.size(); ++index) {
    const auto& port = ports_[index];
    bus::Bus& bus = *port->bus;
    port->pty->start([this, &bus](std::span<const std::uint8_t> bytes, std::uint32_t bps) {
      driver_.catch_up();
      // The kernel took handover_ to bring the bytes here and will take about as long to take
      // the reply back, and the bytes woke this thread, which then waited for a CPU: count them
      // as written that much earlier (docs/timing.md "PTY hand-over", "Late replies").
      const sim::SimDuration waited =
          options_.timing == TimingMode::Manual ? sim::SimDuration{0} : cpu_wait_.since_mark();
      const sim::SimTime arrived = std::max(sim::SimTime{}, scheduler_.now() - handover_ - waited);
      bus.receive(bytes, arrived, bps);
      // Saved before rearm(), which delivers replies due now (every reply under fast and manual
      // timing): an EEPROM write is in the state file before its status reaches the client, so
      // a kill -9 after the acknowledgement cannot lose it.
      save_state_if_changed();
      driver_.rearm();
      finish_handler();  // the trace lines of the request and of a reply sent at once
    });
    nlohmann::ordered_json servos = nlohmann::ordered_json::array();
    for (const auto& servo : bus.servos()) {  // the IDs in force: a state file may change them
      servos.push_back({{"id", servo->id()}, {"model", servo->spec().name}});
    }
    nlohmann::ordered_json ready = {
        {"event", "ready"}, {"port", port->config.name}, {"pty", port->pty->slave_path()}};
    if (port->config.link) {
      ready["link"] = port->config.link->string();
    }
    ready["servos"] = servos;
    ready["control"] = control_->path().string();
    ready["seed"] = injector_.seed();
    out << ready.dump() << std::endl;  // flushed: scripts wait for this line
    log(LogLevel::Info, port->config.name + ": " + std::to_string(port->config.servos.size()) +
                            " servos on " + port->pty->slave_path());
  }
  // Events scheduled before the loop starts (a --scenario's steps) need the timer too.
  driver_.rearm();
  io_.run();
  if (shutting_down_) {
    // Let the shutdown reply reach its client.
    io_.restart();
    io_.run_for(kShutdownFlush);
  }
  finish_handler();
  for (const auto& port : ports_) {
    const bus::BusStats& s = port->bus->stats();
    std::string late;
    if (port->guard) {
      const bus::LatenessSummary l = port->guard->summary();
      late = ", " + std::to_string(l.over[0]) + " replies more than " +
             std::to_string(bus::LatenessSummary::kThresholds[0].count()) + " ms late (at most " +
             std::to_string(std::chrono::duration_cast<std::chrono::microseconds>(l.max).count()) +
             " us), " + std::to_string(l.dropped) + " dropped as late";
    }
    log(LogLevel::Info, port->config.name + ": " + std::to_string(s.frames) + " packets, " +
                            std::to_string(s.replies) + " replies, " +
                            std::to_string(s.bad_checks) + " bad checks, " +
                            std::to_string(s.collisions) + " collisions" + late);
  }
}

}  // namespace dxlemu::app
