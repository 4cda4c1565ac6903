#include "model/servo.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <type_traits>

#include "model/item_hooks.hpp"

namespace dxlemu::model {
namespace {

// Instructions that change nothing the motion model reads: a servo at rest stays at rest and its
// ticks stay skipped, where waking it would cost every servo a tick per instruction a polling
// client sends (a broadcast Ping or a Sync Read reaches them all). Everything else wakes it.
bool only_reads(const wire::Instruction& instruction) {
  return std::visit(
      [](const auto& ins) {
        using T = std::decay_t<decltype(ins)>;
        return std::is_same_v<T, wire::Ping> || std::is_same_v<T, wire::Read> ||
               std::is_same_v<T, wire::Echo> || std::is_base_of_v<wire::SyncRead, T> ||
               std::is_base_of_v<wire::BulkRead, T>;
      },
      instruction);
}

using std::chrono::microseconds;

// The instructions only FEETECH defines (servo_feetech.cpp).
template <class T>
constexpr bool kIsFeetechOnly =
    std::is_same_v<T, wire::StatusReset> || std::is_same_v<T, wire::ParameterBackup> ||
    std::is_same_v<T, wire::ParameterRecovery> || std::is_same_v<T, wire::PositionCalibration>;

// Protocol 1.0 families compute the bit rate of Baud Rate n as 2,000,000 / (n + 1)
// (includes/control_table_baudrate.md) for values their table does not list.
constexpr std::uint32_t kV1BaudBase = 2'000'000;

// Clear option and Control Table Backup options (protocol2.md).
constexpr std::uint8_t kClearMultiTurn = 0x01;
constexpr std::uint8_t kBackupStore = 0x01;
constexpr std::uint8_t kBackupRestore = 0x02;

// Startup Configuration bits
// (includes/docs-partials/x__control_table_60_startup_configuration.mdx).
constexpr std::int64_t kStartupTorqueOn = 0x01;
constexpr std::int64_t kStartupRamRestore = 0x02;

// RAM items a Control Table Backup keeps besides the EEPROM (protocol2.md "Control Table Backup").
constexpr std::array<std::string_view, 9> kBackedUpRam = {
    "velocity_i_gain",      "velocity_p_gain",      "position_d_gain",
    "position_i_gain",      "position_p_gain",      "feedforward_2nd_gain",
    "feedforward_1st_gain", "profile_acceleration", "profile_velocity"};
constexpr std::string_view kIndirectAddressPrefix = "indirect_address_";

// Secondary ID values 253 ~ 255 turn the function off (e-Manual control_table_shadowid include).
constexpr std::int64_t kMaxSecondaryId = 252;

// Bus Watchdog (includes/control_table_buswatchdog.md): 1 ~ 127 in 20 ms units; -1 after expiry.
constexpr std::int64_t kBusWatchdogUnitMs = 20;
constexpr std::int64_t kBusWatchdogError = -1;
// A 1.0 status's LENGTH is one byte and counts the parameters plus 2 (protocol1.md "Length").
constexpr std::size_t kV1MaxStatusParams = 0xFF - 2;

}  // namespace

Servo::Servo(std::shared_ptr<const ModelSpec> spec, std::uint8_t id, sim::SimDuration tick)
    : table_(std::move(spec)), motion_(table_, tick), eeprom_writes_(table_.spec().items.size()) {
  items_.id = table_.index("id");
  items_.baud_rate = table_.index("baud_rate");
  items_.return_delay_time = item({"return_delay_time"});
  // MX-64(2.0) and MX-106(2.0) name address 13 "Protocol Version".
  items_.protocol = item({"protocol_type", "protocol_version"});
  // DYNAMIXEL-Y reports its errors in Error Code(153): the status packet's Alert bit follows it.
  items_.hardware_error_status = item({"hardware_error_status", "error_code"});
  // FEETECH: Response level (address 8) and Torque switch (40).
  items_.status_return_level = item({"status_return_level", "response_status_level"});
  if (table_.spec().traits().secondary_id_addresses) {
    items_.secondary_id = item({"secondary_id"});
  }
  items_.bus_watchdog = item({"bus_watchdog"});
  items_.torque_enable = item({"torque_enable", "torque_switch"});
  items_.registered = item({"registered_instruction", "registered", "async_write_flag"});
  table_.set(items_.id, id);
  // After the ID: with FEETECH's Lock flag, the ID given here counts as set at the factory.
  install_item_hooks(HookScope{table_, &motion_}, HookNeeds::Servo);
  commit_deferred();
}

std::optional<std::size_t> Servo::item(std::initializer_list<std::string_view> keys) const {
  for (const std::string_view key : keys) {
    if (const auto i = spec().index_of(key)) {
      return i;
    }
  }
  return std::nullopt;
}

void Servo::commit_deferred() {
  id_ = static_cast<std::uint8_t>(table_.get(items_.id));
  if (items_.protocol) {
    const std::int64_t v = table_.get(*items_.protocol);
    // Another value (S.BUS, iBUS, RC-PWM; Modbus on a model whose file does not list it) is no
    // protocol of the emulated bus.
    protocol_ = wire::protocol_from_type_value(v);
    if (protocol_ && !spec().speaks(*protocol_)) {
      protocol_.reset();
    }
  } else {
    protocol_ = spec().protocols.front();
  }
  const std::int64_t index = table_.get(items_.baud_rate);
  const auto bps = spec().bps_for_index(index);
  baud_bps_ = bps ? *bps
              : spec().traits().protocol1_firmware
                  ? static_cast<std::uint32_t>(kV1BaudBase / (index + 1))
                  : 0;
  // An item the protocol leaves out has no effect (Modbus RTU: "does not support the Return
  // Delay Time(9) feature").
  const std::int64_t delay =
      speaks_item(items_.return_delay_time)
          ? std::max(table_.get(*items_.return_delay_time), spec().traits().min_return_delay)
          : 0;
  return_delay_ = microseconds(delay * spec().return_delay_unit_us);
}

wire::DeviceFaults Servo::device_faults() const {
  // What the device adds to every status: 2.0's alert bit while Hardware Error Status is not 0,
  // 1.0's hardware error bits (Input Voltage, Overheating, Overload: protocol1.md "Status
  // Packet"), FEETECH's live Servo status, and what a FEETECH model answers to its refusals.
  const auto& hw = items_.hardware_error_status;
  const Refusals refusals = spec().refusals();
  wire::DeviceFaults device;
  device.alert = hw && table_.get(*hw) != 0;
  device.status_bits = motion_.v1_error_bits();
  for (std::size_t c = 0; c < wire::kRefusalClassCount; ++c) {
    device.refusals[c] = refusals.of(static_cast<wire::RefusalClass>(c));
  }
  return device;
}

std::uint8_t Servo::status_error(wire::Outcome outcome) const {
  // The protocol's status vocabulary (wire/protocol_table.hpp) turns the outcome into its error
  // byte, with the device's standing faults.
  return wire::status_error_byte(protocol_.value_or(wire::kDefaultProtocol), outcome,
                                 device_faults());
}

ServoResponse Servo::respond(wire::Outcome outcome, sim::SimDuration processing) const {
  const wire::Protocol protocol = protocol_.value_or(wire::kDefaultProtocol);
  const wire::DeviceFaults device = device_faults();
  ServoResponse r;
  // A refusal the device has no way to say (FEETECH's error byte is its status) may be silence.
  r.replies = !wire::silences(protocol, outcome, device);
  r.error = wire::status_error_byte(protocol, outcome, device);
  r.processing = processing;
  return r;
}

bool Servo::supports_fast_read() const {
  const FastRead fast = spec().traits().fast_read;
  return fast == FastRead::All || (fast == FastRead::SingleAxis && spec().axes == 1);
}

bool Servo::supports_v1_bulk_read() const {
  return spec().traits().v1_bulk_read;
}

ServoResponse Servo::bad_check(std::optional<std::uint8_t> instruction) const {
  ServoResponse r = respond(wire::Outcome::BadCheck, write_time(0));
  const bool answers =
      wire::traits(protocol_.value_or(wire::kDefaultProtocol)).status.answers_bad_check;
  r.replies =
      r.replies && answers && replies_to(instruction == wire::to_byte(wire::InstructionCode::Read));
  return r;
}

bool Servo::speaks_item(const std::optional<std::size_t>& item) const {
  return item && spec().items[*item].present_in(protocol_.value_or(wire::kDefaultProtocol));
}

bool Servo::replies_to(bool is_read) const {
  // Status Return Level left out of the protocol (Modbus RTU): every unicast request is
  // answered.
  const std::optional<std::size_t> srl =
      speaks_item(items_.status_return_level) ? items_.status_return_level : std::nullopt;
  // DYNAMIXEL Status Return Level (includes/control_table_status_return_lv.md): 0 answers Ping
  // only, 1 also Read, 2 everything; FEETECH Response level: 0 Ping and Read, 1 everything.
  const FamilyTraits& t = spec().traits();
  const std::int64_t level = srl ? table_.get(*srl) : t.status_level_all;
  return level >= t.status_level_all || (is_read && level >= t.status_level_reads);
}

TableResult Servo::instruction_write(std::uint16_t address, std::span<const std::uint8_t> data,
                                     wire::Protocol protocol) {
  TableResult result = table_.bus_write(address, data, protocol);
  if (result.ok()) {
    table_.for_each_written([this](std::size_t item) {
      if (spec().items[item].area == Area::Eeprom) {
        ++eeprom_writes_[item];
      }
    });
  }
  return result;
}

sim::SimDuration Servo::write_time(std::size_t bytes) const {
  const Timing& t = spec().timing;
  return microseconds(t.write_us + t.write_per_byte_us * bytes);
}

ServoResponse Servo::from_table(const TableResult& result, sim::SimDuration processing) const {
  return respond(outcome_of(result.error), processing);
}

ServoResponse Servo::execute(const wire::InstructionPacket& packet, Addressing addressing) {
  if (!only_reads(packet.instruction)) {
    motion_.wake();
  }
  const Timing& timing = spec().timing;
  const bool broadcast = addressing == Addressing::Broadcast;
  if (addressing == Addressing::Secondary) {
    return execute_secondary(packet);
  }
  // Status Return Level as it is when the instruction arrives: a Write or Factory Reset that
  // changes the level does not change whether this instruction is answered.
  const bool is_read = std::holds_alternative<wire::Read>(packet.instruction);
  const bool srl_allows = replies_to(is_read);
  ServoResponse r = std::visit(
      [&](const auto& ins) -> ServoResponse {
        using T = std::decay_t<decltype(ins)>;
        if constexpr (std::is_same_v<T, wire::Ping>) {
          // Ping is answered whatever the Status Return Level, broadcast too (protocol2.md "Ping").
          ServoResponse ping;
          ping.replies = true;
          ping.error = status_error(wire::Outcome::Ok);
          ping.processing = microseconds(timing.ping_us);
          if (wire::traits(packet.protocol).ping_reports_model) {
            ping.params = {static_cast<std::uint8_t>(spec().model_number & 0xFF),
                           static_cast<std::uint8_t>(spec().model_number >> 8),
                           spec().firmware_version};
          }
          return ping;
        } else if constexpr (std::is_same_v<T, wire::Read>) {
          if (broadcast) {
            return {};  // "Read Instructions are not executed when sent to the Broadcast ID"
          }
          return read_part(ins.address, ins.length);
        } else if constexpr (std::is_same_v<T, wire::Write>) {
          const TableResult result = instruction_write(ins.address, ins.data, packet.protocol);
          return from_table(result, write_time(ins.data.size()));
        } else if constexpr (std::is_same_v<T, wire::WriteRead>) {
          // Modbus Read/Write Multiple Registers: the write is done before the read; a refused
          // write is the answer. Broadcast: the write only.
          const TableResult result =
              instruction_write(ins.write.address, ins.write.data, packet.protocol);
          if (!result.ok() || broadcast) {
            return from_table(result, write_time(ins.write.data.size()));
          }
          ServoResponse read = read_part(ins.read.address, ins.read.length);
          read.processing += write_time(ins.write.data.size());
          return read;
        } else if constexpr (std::is_same_v<T, wire::Echo>) {
          return from_table({}, microseconds(timing.read_us));
        } else if constexpr (std::is_same_v<T, wire::RegWrite>) {
          // The data is checked on arrival; a refused Reg Write registers nothing.
          const TableResult result = table_.check_write(ins.address, ins.data, packet.protocol);
          if (result.ok()) {
            registered_ = Registered{ins.address, ins.data};
            if (items_.registered) {
              table_.set(*items_.registered, 1);
            }
          }
          return from_table(result, write_time(ins.data.size()));
        } else if constexpr (std::is_same_v<T, wire::Action>) {
          if (!registered_) {
            // protocol2.md "Error": Instruction Error when Action comes without Reg Write.
            return respond(wire::Outcome::NothingRegistered, write_time(0));
          }
          const Registered pending = std::move(*registered_);
          registered_.reset();
          if (items_.registered) {
            table_.set(*items_.registered, 0);
          }
          const TableResult result =
              instruction_write(pending.address, pending.data, packet.protocol);
          return from_table(result, write_time(pending.data.size()));
        } else if constexpr (std::is_same_v<T, wire::FactoryReset>) {
          return do_factory_reset(ins.option, broadcast);
        } else if constexpr (std::is_same_v<T, wire::Reboot>) {
          if (!spec().traits().reboot) {
            return respond(wire::Outcome::UnknownInstruction, write_time(0));
          }
          ServoResponse reboot = from_table({}, write_time(0));
          reboot.reboot_after = true;
          // FEETECH Restart: "status frame: none".
          reboot.replies = spec().traits().reboot_status;
          return reboot;
        } else if constexpr (std::is_same_v<T, wire::Clear>) {
          return do_clear(ins);
        } else if constexpr (std::is_same_v<T, wire::ControlTableBackup>) {
          return do_backup(ins);
        } else if constexpr (kIsFeetechOnly<T>) {
          return execute_feetech(ins);
        } else if constexpr (std::is_same_v<T, wire::UnknownInstruction>) {
          return respond(wire::Outcome::UnknownInstruction, write_time(0));
        } else {
          // Sync/Bulk instructions address several servos: the bus splits them into
          // read_part/write_part calls, so a servo never executes them whole.
          return {};
        }
      },
      packet.instruction);
  if (std::holds_alternative<wire::Ping>(packet.instruction)) {
    return r;
  }
  // No status to broadcast instructions (protocol2.md "Packet ID"); Status Return Level
  // suppresses the status but not the effect (includes/control_table_status_return_lv.md).
  r.replies = r.replies && !broadcast && srl_allows;
  return r;
}

ServoResponse Servo::execute_secondary(const wire::InstructionPacket& packet) {
  // Secondary (Shadow) ID: a group address. "The Status Packet is not returned" and only the RAM
  // area can be changed through it, so Write, Reg Write and Action are executed when they touch
  // RAM only; everything else is ignored (docs/servo.md).
  const auto* write = std::get_if<wire::Write>(&packet.instruction);
  const auto* reg_write = std::get_if<wire::RegWrite>(&packet.instruction);
  if (write != nullptr && !table_.touches_eeprom(write->address, write->data.size())) {
    instruction_write(write->address, write->data, packet.protocol);
  } else if (reg_write != nullptr &&
             !table_.touches_eeprom(reg_write->address, reg_write->data.size())) {
    execute({packet.protocol, id_, *reg_write}, Addressing::Broadcast);
  } else if (std::holds_alternative<wire::Action>(packet.instruction)) {
    execute(packet, Addressing::Broadcast);
  }
  return {};
}

std::optional<std::uint8_t> Servo::secondary_id() const {
  const auto& item_index = items_.secondary_id;
  if (!speaks_item(item_index)) {
    return std::nullopt;
  }
  const std::int64_t v = table_.get(*item_index);
  return v <= kMaxSecondaryId ? std::optional(static_cast<std::uint8_t>(v)) : std::nullopt;
}

std::optional<sim::SimDuration> Servo::bus_watchdog_period() const {
  const auto& watchdog = items_.bus_watchdog;
  if (!watchdog || !items_.torque_enable || table_.get(*items_.torque_enable) == 0 ||
      table_.get(*watchdog) <= 0) {
    return std::nullopt;
  }
  return std::chrono::milliseconds(table_.get(*watchdog) * kBusWatchdogUnitMs);
}

void Servo::expire_bus_watchdog() {
  table_.set("bus_watchdog", kBusWatchdogError);
  // "The DYNAMIXEL will stop": no velocity, and hold where it is.
  if (const auto velocity = item({"goal_velocity"})) {
    table_.set(*velocity, 0);
  }
  motion_.stop();
}

ServoResponse Servo::refuse(const wire::DecodeError& error, bool broadcast) const {
  const bool is_read = error.instruction == wire::to_byte(wire::InstructionCode::Read);
  ServoResponse r =
      respond(error.kind == wire::DecodeErrorKind::BadValue     ? wire::Outcome::DataRange
              : error.kind == wire::DecodeErrorKind::BadAddress ? wire::Outcome::ReadOutside
                                                                : wire::Outcome::BadParameters,
              write_time(0));
  r.replies = r.replies && !broadcast && replies_to(is_read);
  return r;
}

ServoResponse Servo::read_part(std::uint16_t address, std::uint16_t length) {
  const microseconds processing(spec().timing.read_us);
  // More data than a 1.0 status can carry (an X in 1.0 mode has a table long enough to read it):
  // no status could answer with it, so it is refused as "out of the range for use" (protocol1.md
  // "Range Error"), like a read past the table.
  if (protocol_ && wire::has_v1_layout(*protocol_) && length > kV1MaxStatusParams) {
    return respond(wire::Outcome::ReadOutside, processing);
  }
  std::vector<std::uint8_t> data;
  const TableResult result =
      table_.bus_read(address, length, data, protocol_.value_or(wire::kDefaultProtocol));
  // Every read the table refuses reaches outside it: past its end, or (Indirect Address) an
  // address it does not have.
  ServoResponse r =
      respond(result.ok() ? wire::Outcome::Ok : wire::Outcome::ReadOutside, processing);
  r.params = std::move(data);
  return r;
}

void Servo::write_part(std::uint16_t address, std::span<const std::uint8_t> data) {
  motion_.wake();
  if (protocol_) {
    instruction_write(address, data, *protocol_);
  }
}

ServoResponse Servo::do_factory_reset(std::uint8_t option, bool broadcast) {
  ServoResponse r = from_table({}, write_time(0));
  // protocol1.md: "Broadcast ID(0xFE) cannot be used for Factory Reset instruction"; protocol2.md:
  // broadcast with option 0xFF is not executed (MX(2.0) and X from firmware 42).
  const bool broadcast_refused = protocol_ && !wire::traits(*protocol_).broadcast_factory_reset;
  if (broadcast && (broadcast_refused || option == wire::factory_reset::kResetAll)) {
    r.replies = false;
    return r;
  }
  const std::int64_t id = table_.get("id");
  const std::int64_t baud = table_.get("baud_rate");
  table_.load_initial(true);
  motion_.republish();
  if (option == wire::factory_reset::kResetAllButId ||
      option == wire::factory_reset::kResetAllButIdAndBaud) {
    table_.set("id", id);
  }
  if (option == wire::factory_reset::kResetAllButIdAndBaud) {
    table_.set("baud_rate", baud);
  }
  r.reboot_after = true;
  return r;
}

ServoResponse Servo::do_clear(const wire::Clear& clear) {
  if (clear.option != kClearMultiTurn) {
    return respond(wire::Outcome::DataRange, write_time(0));  // reserved options
  }
  // "The Clear instruction can only be executed when the DYNAMIXEL is stopped" (protocol2.md).
  // DYNAMIXEL-Y has no Moving item: its Moving Status says so (bit 2).
  const auto moving = item({"moving"});
  const auto status = item({"moving_status"});
  const bool y_moving = !moving && status && spec().traits().moving_status_motion_and_range &&
                        (table_.get(*status) & kMovingStatusMoving) != 0;
  if ((moving && table_.get(*moving) != 0) || y_moving) {
    return respond(wire::Outcome::ResultFail, write_time(0));
  }
  // Back to an absolute position within one rotation (0 ~ 4095 on X).
  motion_.clear_turns();
  return from_table({}, write_time(0));
}

ServoResponse Servo::do_backup(const wire::ControlTableBackup& backup) {
  // Models with Backup Ready support the instruction (X430/540 fw 45+, X330 fw 46+, P fw 12+).
  const auto ready = item({"backup_ready"});
  if (!ready) {
    return respond(wire::Outcome::UnknownInstruction, write_time(0));
  }
  if (backup.option != kBackupStore && backup.option != kBackupRestore) {
    return respond(wire::Outcome::DataRange, write_time(0));  // reserved options
  }
  // "If Torque Enable is set to '1' (Torque On), a Status Packet with Result Fail will be
  // returned."
  if (table_.get("torque_enable") != 0 ||
      (backup.option == kBackupRestore && !backup_.has_value())) {
    return respond(wire::Outcome::ResultFail, write_time(0));
  }
  ServoResponse r = from_table({}, write_time(0));
  if (backup.option == kBackupStore) {
    backup_ = std::vector<std::uint8_t>(table_.bytes().begin(), table_.bytes().end());
    table_.set(*ready, 1);
    return r;
  }
  // Restore EEPROM from the backup, then reboot ("After processing packets, DYNAMIXEL reboots").
  for (std::size_t i = 0; i < spec().items.size(); ++i) {
    const ItemSpec& s = spec().items[i];
    if (s.area == Area::Eeprom && s.access == Access::ReadWrite) {
      table_.copy_from(i, *backup_);
    }
  }
  r.reboot_after = true;
  return r;
}

void Servo::reboot() {
  table_.load_initial(false);
  registered_.reset();
  if (const auto ready = item({"backup_ready"})) {
    table_.set(*ready, backup_ ? 1 : 0);
  }
  const auto startup = item({"startup_configuration"});
  const std::int64_t config = startup ? table_.get(*startup) : 0;
  if ((config & kStartupRamRestore) != 0 && backup_) {
    for (std::size_t i = 0; i < spec().items.size(); ++i) {
      const ItemSpec& s = spec().items[i];
      const bool kept =
          std::find(kBackedUpRam.begin(), kBackedUpRam.end(), s.key) != kBackedUpRam.end() ||
          s.key.rfind(kIndirectAddressPrefix, 0) == 0;
      if (s.area == Area::Ram && kept) {
        table_.copy_from(i, *backup_);
      }
    }
  }
  if ((config & kStartupTorqueOn) != 0) {
    table_.set("torque_enable", 1);
  }
  commit_deferred();
  // includes/control_table_protocolversion.md (XL330/XC330): with an RC protocol selected, the
  // device switches to Protocol 2.0 when no RC signal is detected during booting. The emulator
  // has no RC input, so that is always the case.
  if (!protocol_) {
    protocol_ = wire::kDefaultProtocol;
  }
  // The shaft and the winding do not reboot: the Present values are refreshed from them.
  motion_.after_reboot();
}

sim::SimDuration Servo::boot_time() const {
  return std::chrono::milliseconds(spec().timing.boot_ms);
}

void Servo::power_off() {
  if (items_.torque_enable) {
    table_.set(*items_.torque_enable, 0);
  }
  motion_.wake();
}

}  // namespace dxlemu::model
