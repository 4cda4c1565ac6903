#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "app/config/model_library.hpp"
#include "scan/scan_link.hpp"
#include "sim/sim_time.hpp"
#include "wire/framer.hpp"
#include "wire/instruction.hpp"
#include "wire/status.hpp"

namespace dxlemu::scan {

/// The protocols a scan looks for unless told: all but Modbus RTU, whose sweep of every address
/// would take as long again as the 1.0 sweep at every rate, for the few models that speak it
/// (docs/robots.md "Cloning a real bus").
std::vector<wire::Protocol> default_scan_protocols();

/// What `dxlemu clone` looks for (docs/robots.md "Cloning a real bus").
struct ScanOptions {
  /// The rates to try, in order; empty: every rate a model of the library offers, the common
  /// ones (1 Mbit/s, 57600, 115200) first.
  std::vector<std::uint32_t> bauds;
  /// The protocols to look for: Protocol 2.0 (broadcast Ping), the 1.0 framing of DYNAMIXEL
  /// 1.0 and FEETECH (a Ping of every ID, then the model number tells the maker), Modbus RTU (a
  /// read of the Model Number from every address). default_scan_protocols() by default.
  std::vector<wire::Protocol> protocols = default_scan_protocols();
  /// The IDs a 1.0, FEETECH or Modbus sweep asks (2.0 finds every ID with one broadcast Ping;
  /// Modbus RTU asks the addresses 1 ~ 247 among them).
  std::uint8_t first_id = 0;
  std::uint8_t last_id = wire::highest_unicast_id();
  /// How long to wait for a reply.
  std::chrono::microseconds timeout{std::chrono::milliseconds(34)};
};

/// One servo a scan found and read.
struct FoundServo {
  std::uint32_t bps = 0;
  wire::Protocol protocol = wire::kDefaultProtocol;
  std::uint8_t id = 0;
  std::uint16_t model_number = 0;
  std::uint8_t firmware = 0;
  /// The model (or the firmware variant) it is; nullptr when the library has no such model.
  std::shared_ptr<const model::ModelSpec> spec;
  /// Its non-volatile items as read (app/daemon/bus_state.hpp is_non_volatile), by address.
  std::vector<std::pair<std::string, std::int64_t>> eeprom;
};

/// The rates a scan tries by default: every rate a model of `library` offers, the common ones
/// first, then the others from the fastest down.
std::vector<std::uint32_t> default_scan_bauds(const app::ModelLibrary& library);

/// Scans a bus through `link` as a careful controller would: at each rate, a Protocol 2.0
/// broadcast Ping, then a 1.0 Ping of every ID, then (when asked) a Modbus read of registers 0
/// and 1 (Model Number) from every address; each servo found is identified by its model number
/// and firmware and its non-volatile items are read. Sends only Ping and Read (Modbus: Read
/// Holding Registers): nothing on the bus changes. `progress` gets a line of text now and then;
/// servos of a model the library lacks are returned with no spec and no items.
std::vector<FoundServo> scan_bus(ScanLink& link, const app::ModelLibrary& library,
                                 const ScanOptions& options,
                                 const std::function<void(const std::string&)>& progress);

}  // namespace dxlemu::scan
