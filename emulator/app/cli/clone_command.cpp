#include "app/cli/clone_command.hpp"

#include <algorithm>
#include <ostream>
#include <stdexcept>

#include "app/config/clone_config.hpp"
#include "io/atomic_file.hpp"
#include "io/serial_scan_link.hpp"
#include "scan/bus_scan.hpp"

namespace dxlemu::app {
namespace {

/// --ids FIRST-LAST (or one ID).
std::pair<std::uint8_t, std::uint8_t> id_range(const std::string& text) {
  const auto dash = text.find('-');
  try {
    std::size_t used = 0;
    const int first = std::stoi(text.substr(0, dash), &used);
    const int last = dash == std::string::npos ? first : std::stoi(text.substr(dash + 1));
    if (first >= 0 && last >= first && last <= wire::highest_unicast_id()) {
      return {static_cast<std::uint8_t>(first), static_cast<std::uint8_t>(last)};
    }
  } catch (const std::logic_error&) {
    // a word where a number should be: refused below
  }
  throw std::invalid_argument("--ids " + text + ": expected FIRST-LAST within 0 ~ " +
                              std::to_string(wire::highest_unicast_id()));
}

// The protocols --protocol spells (the CLI accepted only their spellings); empty: the default
// scan's (all but Modbus RTU).
std::vector<wire::Protocol> protocols_of(const std::vector<std::string>& spellings) {
  if (spellings.empty()) {
    return scan::default_scan_protocols();
  }
  std::vector<wire::Protocol> out;
  for (const std::string& spelling : spellings) {
    if (const auto protocol = wire::protocol_from_spelling(spelling)) {
      out.push_back(*protocol);
    }
  }
  return out;
}

}  // namespace

void clone_bus(const CloneArguments& arguments, const ModelLibrary& library, std::ostream& out,
               std::ostream& progress) {
  scan::ScanOptions options;
  options.bauds = arguments.bauds;
  options.protocols = protocols_of(arguments.protocols);
  std::tie(options.first_id, options.last_id) = id_range(arguments.ids);
  options.timeout = std::chrono::milliseconds(arguments.timeout_ms);

  io::SerialScanLink link(arguments.port);
  const auto report = [&](const std::string& line) {
    progress << "dxlemu clone: " << line << std::endl;
  };
  const std::vector<scan::FoundServo> found = scan::scan_bus(link, library, options, report);
  const auto known = std::count_if(found.begin(), found.end(), [](const scan::FoundServo& servo) {
    return servo.spec != nullptr;
  });
  if (known == 0) {
    throw std::runtime_error("no servo of a known model answered on " + arguments.port);
  }
  const std::string text =
      clone_config(found, arguments.port, arguments.name, arguments.link).dump(2) + "\n";
  if (arguments.out.empty()) {
    out << text;
  } else {
    io::write_file_atomically(arguments.out, text);
  }
  report(std::to_string(known) + (known == 1 ? " servo" : " servos") +
         (arguments.out.empty() ? "" : " written to " + arguments.out));
}

}  // namespace dxlemu::app
