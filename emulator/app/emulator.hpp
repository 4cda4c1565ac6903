#pragma once

#include <boost/asio/io_context.hpp>
#include <filesystem>
#include <memory>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "app/model_library.hpp"
#include "bus/bus.hpp"
#include "io/pty_link.hpp"
#include "io/realtime_driver.hpp"
#include "sim/scheduler.hpp"

namespace dxlemu::app {

/// One servo of a port: a model from the library, its ID, and items to set at power-on (by key,
/// e.g. baud_rate, return_delay_time, protocol_type), as if written before the emulator started.
struct ServoConfig {
  std::string model;
  std::uint8_t id = 1;
  std::vector<std::pair<std::string, std::int64_t>> items;
};

/// One port: a PTY with an optional stable symlink, and its servos.
struct PortConfig {
  std::string name;
  std::optional<std::filesystem::path> link;
  std::vector<ServoConfig> servos;
};

/// The running emulator: one io_context, one thread, a scheduler bound to the wall clock, and a
/// PTY and a Bus per port. Construction opens everything or throws; nothing runs half-configured.
class Emulator {
 public:
  /// Builds every port. Throws std::invalid_argument naming an unknown model, an unknown item or
  /// a value outside its range, std::system_error when a PTY or link cannot be made.
  Emulator(const ModelLibrary& library, const std::vector<PortConfig>& ports);
  ~Emulator();
  Emulator(const Emulator&) = delete;
  Emulator& operator=(const Emulator&) = delete;

  /// Writes one readiness line per port (JSON) to `out`, serves until SIGINT or SIGTERM, then
  /// returns; the destructor removes the links.
  void run(std::ostream& out);

 private:
  struct Port;
  boost::asio::io_context io_;
  sim::Scheduler scheduler_;
  io::RealTimeDriver driver_{io_, scheduler_};
  std::vector<std::unique_ptr<Port>> ports_;
};

}  // namespace dxlemu::app
