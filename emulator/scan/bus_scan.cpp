#include "scan/bus_scan.hpp"

#include <algorithm>
#include <set>

#include "app/daemon/bus_state.hpp"
#include "model/table/item_encoding.hpp"
#include "wire/instruction_decoder.hpp"
#include "wire/modbus_codec.hpp"

namespace dxlemu::scan {
namespace {

// The rates most buses run at, tried first: DYNAMIXEL X and FEETECH factory rates.
constexpr std::uint32_t kCommonBauds[] = {1'000'000, 57'600, 115'200};

// A Protocol 2.0 Ping's status: Model Number (2 bytes, little-endian), Firmware Version.
constexpr std::size_t kPingParams = 3;
// The head of a 1.0-framed table: DYNAMIXEL Model Number (0, 2 bytes) and Firmware Version (2);
// FEETECH firmware (0, 1), END (2: 1 for a big-endian table) and Model Number (3, 2 bytes).
constexpr std::uint16_t kHeadLength = 5;
constexpr std::uint8_t kFeetechBigEndian = 1;
// Items are read in runs of at most this many bytes, joining items this close together.
constexpr std::size_t kMaxReadBytes = 128;
constexpr std::size_t kMaxGapBytes = 16;
// Progress during a 1.0 or Modbus sweep: a line every so many IDs.
constexpr int kProgressEvery = 64;
// A Modbus sweep reads holding registers 0 and 1: the Model Number (bytes 0 and 1) and the two
// bytes after it (DYNAMIXEL-P: Model Information).
constexpr std::uint16_t kModbusHeadLength = 4;

std::uint16_t word(std::uint8_t low, std::uint8_t high) {
  return static_cast<std::uint16_t>(low | (high << 8));
}

std::string protocol_text(wire::Protocol protocol) {
  return std::string(wire::protocol_title(protocol));
}

/// The model of `maker` numbered `number`, running `firmware` when the library has that
/// firmware variant.
std::shared_ptr<const model::ModelSpec> identify(const app::ModelLibrary& library,
                                                 std::uint16_t number, model::Maker maker,
                                                 std::uint8_t firmware) {
  auto spec = library.find(number, maker);
  if (spec && firmware != spec->firmware_version) {
    if (auto variant = library.find(spec->name + "@" + std::to_string(firmware))) {
      spec = variant;
    }
  }
  return spec;
}

/// The runs of addresses that cover `items`: [address, length) pairs.
std::vector<std::pair<std::uint16_t, std::uint16_t>> read_runs(
    const std::vector<const model::ItemSpec*>& items) {
  std::vector<std::pair<std::uint16_t, std::uint16_t>> runs;
  std::size_t start = 0;
  std::size_t end = 0;
  for (const model::ItemSpec* item : items) {
    const bool joins = !runs.empty() && item->address <= end + kMaxGapBytes &&
                       item->end() - start <= kMaxReadBytes;
    if (joins) {
      end = std::max(end, item->end());
      runs.back().second = static_cast<std::uint16_t>(end - start);
      continue;
    }
    start = item->address;
    end = item->end();
    runs.emplace_back(item->address, item->size);
  }
  return runs;
}

class Scanner {
 public:
  Scanner(ScanLink& link, const app::ModelLibrary& library, const ScanOptions& options,
          const std::function<void(const std::string&)>& progress)
      : link_(link), library_(library), options_(options), progress_(progress) {}

  std::vector<FoundServo> run() {
    const std::vector<std::uint32_t> bauds =
        options_.bauds.empty() ? default_scan_bauds(library_) : options_.bauds;
    for (const std::uint32_t bps : bauds) {
      link_.set_baud(bps);
      if (wants(wire::Protocol::V2)) {
        scan_v2(bps);
      }
      if (wants(wire::Protocol::V1) || wants(wire::Protocol::Feetech)) {
        scan_v1(bps);
      }
      if (wants(wire::Protocol::Modbus)) {
        scan_modbus(bps);
      }
    }
    return std::move(found_);
  }

 private:
  bool wants(wire::Protocol protocol) const {
    return std::find(options_.protocols.begin(), options_.protocols.end(), protocol) !=
           options_.protocols.end();
  }

  void scan_v2(std::uint32_t bps) {
    // A broadcast Ping: every 2.0 servo answers, each in its turn (protocol2.md "Ping").
    const auto replies = link_.exchange({wire::Protocol::V2, wire::kBroadcastId, wire::Ping{}},
                                        wire::kMaxIdV2 + 1, options_.timeout);
    std::set<std::uint8_t> seen;
    for (const wire::StatusPacket& status : replies) {
      if (status.params.size() < kPingParams || !seen.insert(status.id).second) {
        continue;
      }
      const std::uint16_t number = word(status.params[0], status.params[1]);
      const std::uint8_t firmware = status.params[2];
      add({bps,
           wire::Protocol::V2,
           status.id,
           number,
           firmware,
           identify(library_, number, model::Maker::Robotis, firmware),
           {}});
    }
    progress_(std::to_string(bps) + " bps, Protocol 2.0: " + std::to_string(seen.size()) +
              " found");
  }

  void scan_v1(std::uint32_t bps) {
    std::size_t count = 0;
    for (int id = options_.first_id; id <= options_.last_id; ++id) {
      if ((id - options_.first_id) % kProgressEvery == 0 && id != options_.first_id) {
        progress_(std::to_string(bps) + " bps, Protocol 1.0 and FEETECH: ID " + std::to_string(id) +
                  "...");
      }
      const auto ident = static_cast<std::uint8_t>(id);
      const auto pong =
          link_.exchange({wire::Protocol::V1, ident, wire::Ping{}}, 1, options_.timeout);
      if (pong.empty() || pong.front().id != ident) {
        continue;
      }
      ++count;
      add(identify_v1(bps, ident));
    }
    progress_(std::to_string(bps) + " bps, Protocol 1.0 and FEETECH: " + std::to_string(count) +
              " found");
  }

  void scan_modbus(std::uint32_t bps) {
    // Modbus RTU has no Ping: a read of the Model Number from each slave address (modbus.md
    // "The register map": register 0 holds table bytes 0 and 1).
    const wire::ProtocolTraits& row = wire::traits(wire::Protocol::Modbus);
    const int first = std::max<int>(options_.first_id, row.min_unicast_id);
    const int last = std::min<int>(options_.last_id, row.max_unicast_id);
    std::size_t count = 0;
    for (int id = first; id <= last; ++id) {
      if ((id - first) % kProgressEvery == 0 && id != first) {
        progress_(std::to_string(bps) + " bps, Modbus RTU: address " + std::to_string(id) + "...");
      }
      const auto ident = static_cast<std::uint8_t>(id);
      const auto head = link_.exchange(
          {wire::Protocol::Modbus, ident, wire::Read{0, kModbusHeadLength}}, 1, options_.timeout);
      if (head.empty() || head.front().id != ident) {
        continue;
      }
      const auto bytes = wire::registers_read(head.front().params);
      if (!bytes || bytes->size() != kModbusHeadLength) {
        progress_("address " + std::to_string(id) + " at " + std::to_string(bps) +
                  " bps (Modbus RTU) answered " +
                  (head.front().error != 0 ? "exception " + std::to_string(head.front().error)
                                           : std::string("a response of another length")) +
                  " to a read of its Model Number; left out");
        continue;
      }
      ++count;
      add(identify_modbus(bps, ident, word((*bytes)[0], (*bytes)[1])));
    }
    progress_(std::to_string(bps) + " bps, Modbus RTU: " + std::to_string(count) + " found");
  }

  /// A servo that answered a Modbus read of its Model Number: a ROBOTIS model that speaks Modbus
  /// RTU, whose Firmware Version is read from where its model file puts it.
  FoundServo identify_modbus(std::uint32_t bps, std::uint8_t id, std::uint16_t number) {
    FoundServo servo{bps, wire::Protocol::Modbus, id, number, 0, nullptr, {}};
    auto spec = library_.find(number, model::Maker::Robotis);
    if (!spec || !spec->speaks(wire::Protocol::Modbus)) {
      return servo;
    }
    if (const model::ItemSpec* firmware = spec->find("firmware_version")) {
      const std::vector<std::uint8_t> bytes = read(servo, firmware->address, firmware->size);
      if (bytes.size() == firmware->size) {
        servo.firmware = bytes[0];
      }
    }
    servo.spec = identify(library_, number, model::Maker::Robotis, servo.firmware);
    return servo;
  }

  /// A servo that answered a 1.0 Ping: DYNAMIXEL 1.0 or FEETECH, by the model number its table
  /// holds where each maker keeps it.
  FoundServo identify_v1(std::uint32_t bps, std::uint8_t id) {
    FoundServo servo{bps, wire::Protocol::V1, id, 0, 0, nullptr, {}};
    const auto head =
        link_.exchange({wire::Protocol::V1, id, wire::Read{0, kHeadLength}}, 1, options_.timeout);
    if (head.empty() || head.front().params.size() != kHeadLength) {
      return servo;
    }
    const std::vector<std::uint8_t>& b = head.front().params;
    servo.model_number = word(b[0], b[1]);
    servo.firmware = b[2];
    if (wants(wire::Protocol::V1)) {
      servo.spec = identify(library_, servo.model_number, model::Maker::Robotis, servo.firmware);
      if (servo.spec) {
        return servo;
      }
    }
    if (wants(wire::Protocol::Feetech)) {
      const bool big = b[2] == kFeetechBigEndian;
      const std::uint16_t number = big ? word(b[4], b[3]) : word(b[3], b[4]);
      auto spec = identify(library_, number, model::Maker::Feetech, b[0]);
      if (spec && (spec->byte_order == model::ByteOrder::Big) == big) {
        servo.protocol = wire::Protocol::Feetech;
        servo.model_number = number;
        servo.firmware = b[0];
        servo.spec = std::move(spec);
      }
    }
    return servo;
  }

  void add(FoundServo servo) {
    if (!servo.spec) {
      progress_("ID " + std::to_string(servo.id) + " at " + std::to_string(servo.bps) + " bps (" +
                protocol_text(servo.protocol) + "): model number " +
                std::to_string(servo.model_number) + " is not in the model library; left out");
    } else {
      read_items(servo);
      progress_("ID " + std::to_string(servo.id) + " at " + std::to_string(servo.bps) + " bps (" +
                protocol_text(servo.protocol) + "): " + servo.spec->name + ", firmware " +
                std::to_string(servo.firmware) + ", " + std::to_string(servo.eeprom.size()) +
                " items read");
    }
    found_.push_back(std::move(servo));
  }

  void read_items(FoundServo& servo) {
    const model::ModelSpec& spec = *servo.spec;
    std::vector<const model::ItemSpec*> items;
    std::size_t absent = 0;
    for (const model::ItemSpec& item : spec.items) {
      if (!app::is_non_volatile(item)) {
        continue;
      }
      // An item the protocol's map leaves out (Modbus RTU's N/A) cannot be read: it keeps its
      // factory value, and has no effect while the servo speaks that protocol.
      if (!item.present_in(servo.protocol)) {
        ++absent;
        continue;
      }
      items.push_back(&item);
    }
    if (absent != 0) {
      progress_("ID " + std::to_string(servo.id) + ": " + std::to_string(absent) +
                " items are not in the " + protocol_text(servo.protocol) +
                " map; left at their factory values");
    }
    std::sort(items.begin(), items.end(),
              [](const auto* a, const auto* b) { return a->address < b->address; });
    for (const auto& [address, length] : read_runs(items)) {
      std::vector<std::uint8_t> bytes = read(servo, address, length);
      for (const model::ItemSpec* item : items) {
        if (item->address < address || item->end() > std::size_t{address} + length) {
          continue;
        }
        std::span<const std::uint8_t> data;
        std::vector<std::uint8_t> alone;
        if (bytes.size() == length) {
          data = std::span(bytes).subspan(item->address - address, item->size);
        } else {
          // The run was refused (an address inside it the servo lacks): item by item.
          alone = read(servo, item->address, item->size);
          if (alone.size() != item->size) {
            progress_("ID " + std::to_string(servo.id) + ": " + item->key +
                      " could not be read; left at its factory value");
            continue;
          }
          data = alone;
        }
        servo.eeprom.emplace_back(item->key, model::decode_value(*item, spec.byte_order, data));
      }
    }
  }

  /// Bytes `address` ~ `address + length - 1` of the servo's table; empty when they did not
  /// come. A protocol of registers (Modbus RTU) reads the whole registers that hold them.
  std::vector<std::uint8_t> read(const FoundServo& servo, std::uint16_t address,
                                 std::uint16_t length) {
    const std::size_t unit = std::max<std::size_t>(wire::traits(servo.protocol).register_bytes, 1);
    const std::size_t first = address / unit * unit;
    const std::size_t end = (std::size_t{address} + length + unit - 1) / unit * unit;
    const auto replies = link_.exchange(
        {servo.protocol, servo.id,
         wire::Read{static_cast<std::uint16_t>(first), static_cast<std::uint16_t>(end - first)}},
        1, options_.timeout);
    if (replies.empty() || replies.front().id != servo.id) {
      return {};
    }
    // A Modbus response's data is a byte count and registers; an exception response has none.
    std::vector<std::uint8_t> params = replies.front().params;
    if (servo.protocol == wire::Protocol::Modbus) {
      params = wire::registers_read(params).value_or(std::vector<std::uint8_t>{});
    }
    // The error byte may report a hardware error (1.0, FEETECH) beside good data: the length
    // tells whether the data came.
    if (params.size() != end - first) {
      return {};
    }
    return {params.begin() + static_cast<std::ptrdiff_t>(address - first),
            params.begin() + static_cast<std::ptrdiff_t>(address - first + length)};
  }

  ScanLink& link_;
  const app::ModelLibrary& library_;
  const ScanOptions& options_;
  const std::function<void(const std::string&)>& progress_;
  std::vector<FoundServo> found_;
};

}  // namespace

std::vector<wire::Protocol> default_scan_protocols() {
  std::vector<wire::Protocol> out = wire::all_protocols();
  std::erase(out, wire::Protocol::Modbus);
  return out;
}

std::vector<std::uint32_t> default_scan_bauds(const app::ModelLibrary& library) {
  std::set<std::uint32_t, std::greater<>> offered;
  for (const auto& [name, spec] : library.models()) {
    for (const model::BaudRate& rate : spec->baud_rates) {
      offered.insert(rate.bps);
    }
  }
  std::vector<std::uint32_t> bauds;
  for (const std::uint32_t bps : kCommonBauds) {
    if (offered.erase(bps) != 0) {
      bauds.push_back(bps);
    }
  }
  bauds.insert(bauds.end(), offered.begin(), offered.end());
  return bauds;
}

std::vector<FoundServo> scan_bus(ScanLink& link, const app::ModelLibrary& library,
                                 const ScanOptions& options,
                                 const std::function<void(const std::string&)>& progress) {
  return Scanner(link, library, options, progress).run();
}

}  // namespace dxlemu::scan
