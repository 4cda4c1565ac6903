#include "app/daemon/emulator.hpp"

#include <algorithm>
#include <boost/asio/post.hpp>
#include <boost/asio/signal_set.hpp>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <random>

#include "app/config/make_servo.hpp"
#include "app/config/trajectory_file.hpp"
#include "app/config/trajectory_library.hpp"
#include "app/config/web_address.hpp"
#include "app/daemon/bus_port_view.hpp"
#include "app/daemon/log.hpp"
#include "app/daemon/port_link_chain.hpp"
#include "bus/bus.hpp"
#include "control/reply.hpp"
#include "control/scenario.hpp"
#include "faults/port_faults.hpp"
#include "io/atomic_file.hpp"
#include "io/pty_handover.hpp"
#include "io/pty_link.hpp"
#include "io/realtime_scheduling.hpp"
#include "physics/mjcf_world.hpp"

namespace dxlemu::app {
namespace {

// After a control API shutdown, how long replies still queued get to reach their clients.
constexpr std::chrono::milliseconds kShutdownFlush{100};
// The first web connection's id: above any the control socket gives out.
constexpr std::uint64_t kFirstWebConnection = std::uint64_t{1} << 62;
// How far the physics world, and servos a hand moves, may lag simulated time between reads.
constexpr std::chrono::milliseconds kMotionCatchUp{10};

// 128 random bits as 32 hex digits: the web interface's access token (docs/web.md).
std::string random_token() {
  std::random_device device;  // getrandom(2) on Linux
  std::string token;
  for (int i = 0; i < 4; ++i) {
    char word[9];
    std::snprintf(word, sizeof word, "%08x", device());
    token += word;
  }
  return token;
}

}  // namespace

struct Emulator::Port {
  PortConfig config;
  std::unique_ptr<io::PtyLink> pty;
  std::unique_ptr<PortLinkChain> links;  // between the bus and the PTY
  std::unique_ptr<bus::Bus> bus;
  std::unique_ptr<faults::PortFaults> faults;  // the fault rules as the bus meets them
  std::unique_ptr<BusPortView> view;           // the bus as the control API sees it
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
  state_ =
      std::make_unique<StateKeeper>(StateKeeper::open(options_.state, io::write_file_atomically));
  // The one wall-clock read of the capture: simulated time started with the driver, just now.
  const auto pcap_start = std::chrono::duration_cast<std::chrono::microseconds>(
      std::chrono::system_clock::now().time_since_epoch());
  trace_ = TraceFanOut::open(options_.trace, options_.pcap, pcap_start);
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
    port->links = std::make_unique<PortLinkChain>(
        *port->pty, scheduler_, [this] { return driver_.wall_now(); }, port_config, options_);
    port->bus = std::make_unique<bus::Bus>(scheduler_, port->links->bus_side());
    port->view = std::make_unique<BusPortView>(*port->bus, port->links->guard());
    std::vector<control::JointView> joint_names;
    for (const JointName& joint : port_config.joints) {
      joint_names.push_back({joint.name, joint.id, joint.range_deg});
    }
    port->view->set_joints(std::move(joint_names));
    if (options_.timing != TimingMode::Realtime) {
      port->bus->set_reply_timing(bus::ReplyTiming::Immediate);
    }
    for (const ServoConfig& servo : port_config.servos) {
      port->bus->add_servo(make_servo(library, servo, options.tick));
    }
    // One observer feeds the trace file, the capture and the control API's trace subscribers,
    // so all can be on at once.
    // Outside manual timing, each reply's trace record says how late it went out.
    port->bus->set_observer(trace_->observer(
        port_config.name, ports_.size(),
        options_.timing == TimingMode::Manual ? TraceFanOut::Clock{} : TraceFanOut::Clock([this] {
          return driver_.wall_now();
        })));
    state_->add_port(port_config.name, *port->bus);
    port->faults = std::make_unique<faults::PortFaults>(scheduler_, port->bus->servos());
    port->faults->set_rules(&injector_, port_config.name);
    port->bus->set_faults(port->faults.get());
    ports_.push_back(std::move(port));
  }
  state_->restore();
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
  }
  // EEPROM also changes in scheduled events (a reboot that restores a Control Table Backup).
  driver_.set_after_events([this] { finish_handler(); });
  api_ = std::make_unique<control::Api>(*this);
  control_ = std::make_unique<io::ControlServer>(
      io_, options_.control.value_or(default_control_path()),
      [this](std::string_view line, io::ControlSession& session) {
        // The session stays valid until on_close, which ends its events.
        return handle_request(line, {session.id(), [&session](std::string event) {
                                       session.send(std::move(event));
                                     }});
      },
      io::ControlServer::Replies{control::oversize_line, control::internal_error_line});
  control_->on_close([this](io::ControlSession& session) { api_->closed(session.id()); });
  if (options_.web) {
    start_web();
  }
  start_hands();
  keep_motion_caught_up();
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

void Emulator::start_hands() {
  // Through the control API, as hand.play and hand.sweep: one set of checks and one mechanism.
  for (const auto& port : ports_) {
    for (const HandStart& hand : port->config.hands) {
      nlohmann::ordered_json request = nlohmann::ordered_json::parse(hand.request);
      request["port"] = port->config.name;
      const nlohmann::ordered_json reply = api_->run(request);
      if (reply["ok"] != true) {
        throw std::invalid_argument(hand.origin + ": " + reply["error"].get<std::string>());
      }
      log(LogLevel::Info, port->config.name + ": " + hand.origin + ": a hand holds " +
                              std::to_string(reply["result"]["joints"].size()) + " joint(s) for " +
                              reply["result"]["duration_s"].dump() + " s" +
                              (reply["result"]["loop"] == true ? ", looping" : ""));
    }
  }
}

std::string Emulator::handle_request(std::string_view line, const control::Connection& connection) {
  driver_.catch_up();
  std::string reply = api_->handle(line, &connection);
  keep_motion_caught_up();
  driver_.rearm();
  finish_handler();  // a set of an EEPROM item is kept like a bus write
  return reply;
}

void Emulator::start_web() {
  io::WebServerOptions web;
  web.address = options_.web->address;
  web.port = options_.web->port;
  web.token = random_token();
  web.web_root = options_.web_root.empty() ? shipped_web_dir() : options_.web_root;
  // Both servers reach the same API, which tells its connections (trace and sample
  // subscribers) apart by id: the web's are numbered apart from the control socket's.
  web.first_session_id = kFirstWebConnection;
  web_ = std::make_unique<io::WebServer>(
      io_, std::move(web),
      [this](std::string_view line, io::WebSession& session) {
        control::Connection connection{
            session.id(), [&session](std::string event) { session.send_event(std::move(event)); }};
        connection.read_only = options_.web_read_only;
        return handle_request(line, connection);
      },
      io::WebServer::Replies{control::internal_error_line});
  web_->on_close([this](io::WebSession& session) { api_->closed(session.id()); });
  if (!web_->loopback()) {
    log(LogLevel::Warn, "--web " + options_.web->address +
                            ": the web interface is reachable from other machines; anyone "
                            "with its URL (the token) can drive the bus");
  }
  log(LogLevel::Info, std::string("web interface") +
                          (options_.web_read_only ? " (read-only)" : "") + ": " + web_->url());
}

void Emulator::subscribe_trace(const control::Connection& connection,
                               std::vector<std::string> ports) {
  trace_->subscribe(connection, std::move(ports));
}

void Emulator::unsubscribe_trace(std::uint64_t connection) {
  trace_->unsubscribe(connection);
}

void Emulator::schedule_in(sim::SimDuration delay, std::function<void()> action) {
  // A scenario step may put a hand on a servo.
  scheduler_.schedule_at(scheduler_.now() + delay, [this, action = std::move(action)] {
    action();
    keep_motion_caught_up();
  });
}

std::shared_ptr<const model::Trajectory> Emulator::trajectory(const std::string& file) {
  return std::make_shared<const model::Trajectory>(
      read_trajectory_file(find_trajectory(file, options_.trajectory_dirs)));
}

bool Emulator::motion_to_catch_up() const {
  // A hand keeps its servos moving whoever reads them; so does a world its joints.
  return world_ != nullptr || std::any_of(ports_.begin(), ports_.end(), [](const auto& port) {
           const auto& servos = port->bus->servos();
           return std::any_of(servos.begin(), servos.end(),
                              [](const auto& servo) { return servo->motion().hand() != nullptr; });
         });
}

void Emulator::keep_motion_caught_up() {
  if (catching_up_ || !motion_to_catch_up()) {
    return;
  }
  catching_up_ = true;
  scheduler_.schedule_at(scheduler_.now() + kMotionCatchUp, [this] {
    catching_up_ = false;
    if (world_) {
      world_->advance_to(scheduler_.now());
    }
    for (const auto& port : ports_) {
      port->bus->catch_up();
    }
    keep_motion_caught_up();
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
      info["adapter"] = p->links->adapter_info();
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

std::string_view Emulator::timing() const {
  switch (options_.timing) {
    case TimingMode::Realtime:
      return "realtime";
    case TimingMode::Fast:
      return "fast";
    case TimingMode::Manual:
      return "manual";
  }
  return "realtime";
}

void Emulator::step_clock(sim::SimDuration d) {
  scheduler_.advance_by(d);
}

void Emulator::request_shutdown() {
  log(LogLevel::Info, "stopping on the control API's shutdown");
  shutting_down_ = true;
  boost::asio::post(io_, [this] { io_.stop(); });
}

void Emulator::finish_handler() {
  // Once per handler rather than per line: a round trip writes two trace lines, and a reader
  // (tail -f) still sees each packet as soon as the daemon is done with it.
  trace_->flush();
  state_->save_if_changed();
  cpu_wait_.mark();  // the thread goes back to waiting for the next handler
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
      state_->save_if_changed();
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
    if (web_) {
      ready["web"] = web_->url();
    }
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
    log(LogLevel::Info, port->config.name + ": " + std::to_string(s.frames) + " packets, " +
                            std::to_string(s.replies) + " replies, " +
                            std::to_string(s.bad_checks) + " bad checks, " +
                            std::to_string(s.collisions) + " collisions" +
                            port->links->lateness_summary());
  }
}

}  // namespace dxlemu::app
