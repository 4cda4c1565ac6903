#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "app/daemon/bus_state.hpp"
#include "bus/bus.hpp"

namespace dxlemu::app {

/// Keeps every servo's non-volatile memory across restarts (--state, docs/config.md "State
/// file"): reads the state file when made, restores it into the servos once every port is
/// added, and writes it again whenever an EEPROM byte changed. Without a state file it only
/// commits the servos' start-up settings. It does no I/O of its own: the file is read by open()
/// and written through the Writer it is given (the daemon's is atomic).
class StateKeeper {
 public:
  /// Writes `content` as the whole of `path`, so that a crash leaves the old or the new file.
  using Writer = std::function<void(const std::filesystem::path& path, std::string_view content)>;

  /// A keeper of `file` (none: nothing is restored or written) whose content was `saved`
  /// (read_state()).
  StateKeeper(std::optional<std::filesystem::path> file, BusState saved, Writer write);

  /// A keeper of `file` (none: nothing is restored or written), read now: an absent file is a
  /// first run. Throws ConfigError for a file that is not a state file.
  static StateKeeper open(const std::optional<std::filesystem::path>& file, Writer write);

  /// Keeps the servos of `bus`, the port named `port`; `bus` must outlive the keeper. Ports are
  /// added in config order, before restore().
  void add_port(std::string port, bus::Bus& bus);

  /// Restores each servo's saved items where the file has a servo of the same model at the same
  /// place on the same port (another model warns and starts from its config), commits every
  /// servo's deferred settings (the ID, baud and protocol of the config and the state apply),
  /// then writes the file. Throws ConfigError for a saved value the servo refuses.
  void restore();

  /// Writes the state file if any servo's EEPROM changed since the last write. Cheap while
  /// nothing changed: called after every PTY read and control request.
  void save_if_changed();

 private:
  struct Port {
    std::string name;
    bus::Bus* bus;
  };
  std::optional<std::filesystem::path> file_;
  Writer write_;
  BusState saved_;  // the file as it was when the keeper was made
  std::vector<Port> ports_;
  std::vector<std::vector<std::uint8_t>> saved_eeprom_;  // per servo, ports in order
  /// The servos' ControlTable::eeprom_changes() summed when saved_eeprom_ was last compared with
  /// them (each count only grows, so an equal sum means no EEPROM byte changed since).
  std::optional<std::uint64_t> checked_eeprom_changes_;
};

}  // namespace dxlemu::app
