#include "app/emulator.hpp"

#include <boost/asio/signal_set.hpp>
#include <csignal>
#include <nlohmann/json.hpp>
#include <stdexcept>

namespace dxlemu::app {

struct Emulator::Port {
  PortConfig config;
  std::unique_ptr<io::PtyLink> pty;
  std::unique_ptr<bus::Bus> bus;
};

Emulator::Emulator(const ModelLibrary& library, const std::vector<PortConfig>& ports) {
  for (const PortConfig& config : ports) {
    auto port = std::make_unique<Port>();
    port->config = config;
    port->pty = std::make_unique<io::PtyLink>(io_, config.link);
    port->bus = std::make_unique<bus::Bus>(scheduler_, *port->pty);
    for (const ServoConfig& servo : config.servos) {
      const auto spec = library.find(servo.model);
      if (!spec) {
        throw std::invalid_argument("unknown model \"" + servo.model +
                                    "\" (dxlemu models lists them)");
      }
      model::Servo& added = port->bus->add_servo(std::make_unique<model::Servo>(spec, servo.id));
      for (const auto& [key, value] : servo.items) {
        const model::ItemSpec* item = spec->find(key);
        const std::string who = "servo " + std::to_string(servo.id) + " (" + servo.model + "): ";
        if (item == nullptr) {
          throw std::invalid_argument(who + "no item \"" + key + "\"");
        }
        if (!item->in_range(value)) {
          throw std::invalid_argument(who + key + " " + std::to_string(value) +
                                      " is outside its range " + std::to_string(item->min) + " ~ " +
                                      std::to_string(item->max));
        }
        added.table().set(key, value);
      }
      added.commit_deferred();
    }
    ports_.push_back(std::move(port));
  }
}

Emulator::~Emulator() = default;

void Emulator::run(std::ostream& out) {
  // Signals first: a script may send SIGTERM the moment it reads the readiness line.
  boost::asio::signal_set signals(io_, SIGINT, SIGTERM);
  signals.async_wait([this](const boost::system::error_code& ec, int) {
    if (!ec) {
      io_.stop();
    }
  });
  for (const auto& port : ports_) {
    bus::Bus& bus = *port->bus;
    port->pty->start([this, &bus](std::span<const std::uint8_t> bytes, std::uint32_t bps) {
      driver_.catch_up();
      bus.receive(bytes, scheduler_.now(), bps);
      driver_.rearm();
    });
    nlohmann::ordered_json servos = nlohmann::ordered_json::array();
    for (const ServoConfig& s : port->config.servos) {
      servos.push_back({{"id", s.id}, {"model", s.model}});
    }
    nlohmann::ordered_json ready = {
        {"event", "ready"}, {"port", port->config.name}, {"pty", port->pty->slave_path()}};
    if (port->config.link) {
      ready["link"] = port->config.link->string();
    }
    ready["servos"] = servos;
    out << ready.dump() << std::endl;  // flushed: scripts wait for this line
  }
  io_.run();
}

}  // namespace dxlemu::app
