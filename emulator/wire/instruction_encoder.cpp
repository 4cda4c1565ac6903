#include "wire/instruction_encoder.hpp"

#include <algorithm>
#include <initializer_list>
#include <stdexcept>
#include <string>
#include <type_traits>

#include "wire/modbus_codec.hpp"
#include "wire/packet_encoder.hpp"

namespace dxlemu::wire {
namespace {

// Writes parameter fields; the counterpart of the decoder's ParamReader. Address and length
// fields take 1 byte in Protocol 1.0 and FEETECH and 2 bytes (little-endian) in 2.0.
class ParamWriter {
 public:
  explicit ParamWriter(Protocol protocol) : protocol_(protocol) {}

  void byte(std::uint8_t b) { out_.push_back(b); }
  void u16(std::uint16_t v) {
    out_.push_back(static_cast<std::uint8_t>(v & 0xFFU));
    out_.push_back(static_cast<std::uint8_t>(v >> 8));
  }
  void field(std::uint16_t v, const char* what) {
    if (!has_v1_layout(protocol_)) {
      u16(v);
      return;
    }
    if (v > 0xFF) {
      throw std::invalid_argument(std::string(protocol_title(protocol_)) + " " + what + " " +
                                  std::to_string(v) + " does not fit one byte");
    }
    byte(static_cast<std::uint8_t>(v));
  }
  void bytes(const std::vector<std::uint8_t>& data) {
    out_.insert(out_.end(), data.begin(), data.end());
  }
  // Throws unless the packet's protocol is one of `protocols`: `name` does not exist in it.
  void require(std::initializer_list<Protocol> protocols, const char* name) const {
    if (std::find(protocols.begin(), protocols.end(), protocol_) == protocols.end()) {
      throw std::invalid_argument(std::string(name) + " does not exist in " +
                                  std::string(protocol_title(protocol_)));
    }
  }
  void require_v2(const char* name) const { require({Protocol::V2}, name); }
  void require_dynamixel(const char* name) const { require({Protocol::V1, Protocol::V2}, name); }
  void require_feetech(const char* name) const { require({Protocol::Feetech}, name); }
  bool v1() const { return protocol_ == Protocol::V1; }
  std::vector<std::uint8_t>& params() { return out_; }

 private:
  Protocol protocol_;
  std::vector<std::uint8_t> out_;
};

struct ParamsEncoder {
  ParamWriter& w;

  void operator()(const Ping&) const {}
  void operator()(const Action&) const {}
  void operator()(const Reboot&) const {}
  void operator()(const Read& r) const {
    w.field(r.address, "address");
    w.field(r.length, "length");
  }
  void operator()(const Write& x) const { address_and_data(x.address, x.data); }
  void operator()(const RegWrite& x) const { address_and_data(x.address, x.data); }
  void operator()(const FactoryReset& f) const {
    w.require_dynamixel("factory_reset");
    if (w.v1()) {
      if (f.option != factory_reset::kResetAll) {
        throw std::invalid_argument("Protocol 1.0 Factory Reset has no options");
      }
      return;
    }
    w.byte(f.option);
  }
  void operator()(const Clear& c) const { option_and_data("clear", c.option, c.data); }
  void operator()(const ControlTableBackup& c) const {
    option_and_data("control_table_backup", c.option, c.data);
  }
  void operator()(const SyncRead& r) const {
    w.require({Protocol::V2, Protocol::Feetech}, "sync_read");
    sync_read(r);
  }
  void operator()(const FastSyncRead& r) const {
    w.require_v2("fast_sync_read");
    sync_read(r);
  }
  void operator()(const SyncWrite& s) const {
    w.field(s.address, "address");
    w.field(s.length, "length");
    for (const SyncWriteTarget& t : s.targets) {
      if (t.data.size() != s.length) {
        throw std::invalid_argument("sync_write data for ID " + std::to_string(t.id) + " is " +
                                    std::to_string(t.data.size()) + " bytes, length says " +
                                    std::to_string(s.length));
      }
      w.byte(t.id);
      w.bytes(t.data);
    }
  }
  void operator()(const BulkRead& r) const {
    w.require_dynamixel("bulk_read");
    if (w.v1()) {
      // protocol1.md "Bulk Read": 0x00, then [length, ID, address] per device.
      w.byte(kV1BulkReadLeadByte);
      for (const BulkReadTarget& t : r.targets) {
        w.field(t.length, "length");
        w.byte(t.id);
        w.field(t.address, "address");
      }
      return;
    }
    bulk_read_v2(r);
  }
  void operator()(const FastBulkRead& r) const {
    w.require_v2("fast_bulk_read");
    bulk_read_v2(r);
  }
  void operator()(const BulkWrite& b) const {
    w.require_v2("bulk_write");
    for (const BulkWriteTarget& t : b.targets) {
      w.byte(t.id);
      w.u16(t.address);
      w.u16(static_cast<std::uint16_t>(t.data.size()));
      w.bytes(t.data);
    }
  }
  void operator()(const ParameterRecovery&) const { w.require_feetech("parameter_recovery"); }
  void operator()(const ParameterBackup&) const { w.require_feetech("parameter_backup"); }
  void operator()(const StatusReset&) const { w.require_feetech("status_reset"); }
  void operator()(const PositionCalibration& p) const {
    w.require_feetech("position_calibration");
    if (p.position) {
      w.u16(*p.position);  // low byte first (protocol-ft-scs.md 4.9, Example 11)
    }
  }
  void operator()(const UnknownInstruction& u) const { w.bytes(u.params); }
  // Modbus RTU's own; encode_instruction hands Modbus packets to encode_modbus_request.
  void operator()(const WriteRead&) const { w.require({Protocol::Modbus}, "write_read"); }
  void operator()(const Echo&) const { w.require({Protocol::Modbus}, "echo"); }

  void address_and_data(std::uint16_t address, const std::vector<std::uint8_t>& data) const {
    w.field(address, "address");
    w.bytes(data);
  }
  void option_and_data(const char* name, std::uint8_t option,
                       const std::vector<std::uint8_t>& data) const {
    w.require_v2(name);
    w.byte(option);
    w.bytes(data);
  }
  void sync_read(const SyncRead& r) const {
    w.field(r.address, "address");
    w.field(r.length, "length");
    w.bytes(r.ids);
  }
  void bulk_read_v2(const BulkRead& r) const {
    for (const BulkReadTarget& t : r.targets) {
      w.byte(t.id);
      w.u16(t.address);
      w.u16(t.length);
    }
  }
};

// The instructions only FEETECH defines; their codes are FeetechInstructionCode values.
template <class T>
constexpr bool kIsFeetechOnly =
    std::is_same_v<T, ParameterRecovery> || std::is_same_v<T, ParameterBackup> ||
    std::is_same_v<T, StatusReset> || std::is_same_v<T, PositionCalibration>;

template <class T>
constexpr std::uint8_t feetech_code_of() {
  if constexpr (std::is_same_v<T, ParameterRecovery>) {
    return to_byte(FeetechInstructionCode::ParameterRecovery);
  } else if constexpr (std::is_same_v<T, ParameterBackup>) {
    return to_byte(FeetechInstructionCode::ParameterBackup);
  } else if constexpr (std::is_same_v<T, StatusReset>) {
    return to_byte(FeetechInstructionCode::StatusReset);
  } else {
    static_assert(std::is_same_v<T, PositionCalibration>, "not a FEETECH-only instruction");
    return to_byte(FeetechInstructionCode::PositionCalibration);
  }
}

template <class T>
constexpr InstructionCode code_of() {
  if constexpr (std::is_same_v<T, Ping>) {
    return InstructionCode::Ping;
  } else if constexpr (std::is_same_v<T, Read>) {
    return InstructionCode::Read;
  } else if constexpr (std::is_same_v<T, Write>) {
    return InstructionCode::Write;
  } else if constexpr (std::is_same_v<T, RegWrite>) {
    return InstructionCode::RegWrite;
  } else if constexpr (std::is_same_v<T, Action>) {
    return InstructionCode::Action;
  } else if constexpr (std::is_same_v<T, FactoryReset>) {
    return InstructionCode::FactoryReset;
  } else if constexpr (std::is_same_v<T, Reboot>) {
    return InstructionCode::Reboot;
  } else if constexpr (std::is_same_v<T, Clear>) {
    return InstructionCode::Clear;
  } else if constexpr (std::is_same_v<T, ControlTableBackup>) {
    return InstructionCode::ControlTableBackup;
  } else if constexpr (std::is_same_v<T, SyncRead>) {
    return InstructionCode::SyncRead;
  } else if constexpr (std::is_same_v<T, FastSyncRead>) {
    return InstructionCode::FastSyncRead;
  } else if constexpr (std::is_same_v<T, SyncWrite>) {
    return InstructionCode::SyncWrite;
  } else if constexpr (std::is_same_v<T, BulkRead>) {
    return InstructionCode::BulkRead;
  } else if constexpr (std::is_same_v<T, FastBulkRead>) {
    return InstructionCode::FastBulkRead;
  } else if constexpr (std::is_same_v<T, BulkWrite>) {
    return InstructionCode::BulkWrite;
  } else {
    static_assert(!std::is_same_v<T, T>, "every Instruction alternative needs a code");
  }
}

}  // namespace

std::uint8_t instruction_code(const Instruction& instruction) {
  return std::visit(
      [](const auto& x) -> std::uint8_t {
        using T = std::decay_t<decltype(x)>;
        if constexpr (std::is_same_v<T, UnknownInstruction>) {
          return x.instruction;
        } else if constexpr (kIsFeetechOnly<T>) {
          return feetech_code_of<T>();
        } else if constexpr (std::is_same_v<T, WriteRead>) {
          return to_byte(ModbusFunction::ReadWriteMultipleRegisters);
        } else if constexpr (std::is_same_v<T, Echo>) {
          return to_byte(ModbusFunction::Diagnostics);
        } else {
          return to_byte(code_of<T>());
        }
      },
      instruction);
}

std::uint8_t instruction_code(Protocol protocol, const Instruction& instruction) {
  if (protocol == Protocol::Modbus) {
    return modbus_function_of(instruction).value_or(instruction_code(instruction));
  }
  return instruction_code(instruction);
}

std::vector<std::uint8_t> encode_instruction(const InstructionPacket& packet) {
  if (packet.protocol == Protocol::Modbus) {
    return encode_modbus_request(packet);
  }
  ParamWriter writer(packet.protocol);
  std::visit(ParamsEncoder{writer}, packet.instruction);
  return encode_packet(packet.protocol, packet.id, instruction_code(packet.instruction),
                       writer.params());
}

}  // namespace dxlemu::wire
