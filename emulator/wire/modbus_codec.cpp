#include "wire/modbus_codec.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "wire/crc16_modbus.hpp"

namespace dxlemu::wire {
namespace {

// modbus-rtu.md "Function codes a register server offers": quantities per request.
constexpr std::uint16_t kMaxReadRegisters = 125;
constexpr std::uint16_t kMaxWriteRegisters = 123;
constexpr std::uint16_t kMaxReadWriteWriteRegisters = 121;
constexpr std::uint16_t kReturnQueryData = 0x0000;
constexpr std::uint8_t kExceptionBit = 0x80;
constexpr std::size_t kRegisterBytes = 2;
// The control table's byte addresses are 16 bits: a register past 0x7FFF has no bytes there.
constexpr std::uint32_t kByteAddressLimit = 0x10000;

std::uint16_t be16(std::span<const std::uint8_t> data, std::size_t at) {
  return static_cast<std::uint16_t>((data[at] << 8) | data[at + 1]);
}

void put_be16(std::vector<std::uint8_t>& out, std::uint16_t value) {
  out.push_back(static_cast<std::uint8_t>(value >> 8));
  out.push_back(static_cast<std::uint8_t>(value & 0xFFU));
}

// Registers as they travel (big-endian each) to control-table bytes (little-endian).
std::vector<std::uint8_t> table_order(std::span<const std::uint8_t> registers) {
  std::vector<std::uint8_t> out(registers.size());
  for (std::size_t i = 0; i + 1 < registers.size(); i += kRegisterBytes) {
    out[i] = registers[i + 1];
    out[i + 1] = registers[i];
  }
  return out;
}

struct Request {
  const Frame& frame;
  std::string_view name;

  DecodeError fail(DecodeErrorKind kind, const std::string& rule) const {
    return DecodeError{kind, frame.id, frame.instruction, std::string(name) + " " + rule};
  }
  std::optional<DecodeError> size_is(std::size_t bytes, const std::string& layout) const {
    if (frame.params.size() != bytes) {
      return fail(
          DecodeErrorKind::BadLength,
          "needs " + layout + ", got " + std::to_string(frame.params.size()) + " data bytes");
    }
    return std::nullopt;
  }
  // A quantity outside 1 ~ max (exception 03 comes before the address check, exception 02).
  std::optional<DecodeError> quantity(std::uint16_t count, std::uint16_t max,
                                      const char* what) const {
    if (count == 0 || count > max) {
      return fail(DecodeErrorKind::BadValue, std::string(what) + " " + std::to_string(count) +
                                                 " is outside 1 ~ " + std::to_string(max));
    }
    return std::nullopt;
  }
  std::optional<DecodeError> reachable(std::uint16_t start, std::uint16_t count) const {
    if ((std::uint32_t{start} + count) * kRegisterBytes > kByteAddressLimit) {
      return fail(DecodeErrorKind::BadAddress, "registers " + std::to_string(start) + " ~ " +
                                                   std::to_string(start + count - 1) +
                                                   " are beyond any control table");
    }
    return std::nullopt;
  }
};

using Decoded = DecodeResult<Instruction>;

Read read_of(std::uint16_t start, std::uint16_t count) {
  return Read{static_cast<std::uint16_t>(start * kRegisterBytes),
              static_cast<std::uint16_t>(count * kRegisterBytes)};
}

Decoded decode_read(const Request& r) {
  if (auto e = r.size_is(4, "4 data bytes (start, quantity)")) {
    return *e;
  }
  const std::uint16_t start = be16(r.frame.params, 0);
  const std::uint16_t count = be16(r.frame.params, 2);
  if (auto e = r.quantity(count, kMaxReadRegisters, "quantity")) {
    return *e;
  }
  if (auto e = r.reachable(start, count)) {
    return *e;
  }
  return read_of(start, count);
}

Decoded decode_write_single(const Request& r) {
  if (auto e = r.size_is(4, "4 data bytes (address, value)")) {
    return *e;
  }
  const std::uint16_t reg = be16(r.frame.params, 0);
  if (auto e = r.reachable(reg, 1)) {
    return *e;
  }
  return Write{static_cast<std::uint16_t>(reg * kRegisterBytes),
               table_order(std::span(r.frame.params).subspan(2, 2))};
}

// Start, quantity, byte count and values from `at` (Write Multiple Registers, and the write half
// of Read/Write Multiple Registers).
DecodeResult<Write> decode_values(const Request& r, std::size_t at, std::uint16_t max) {
  const auto& p = r.frame.params;
  const std::uint16_t start = be16(p, at);
  const std::uint16_t count = be16(p, at + 2);
  const std::uint8_t byte_count = p[at + 4];
  if (auto e = r.quantity(count, max, "write quantity")) {
    return *e;
  }
  if (byte_count != count * kRegisterBytes) {
    return r.fail(DecodeErrorKind::BadValue, "byte count " + std::to_string(byte_count) +
                                                 " is not twice the quantity (" +
                                                 std::to_string(count) + ")");
  }
  if (p.size() != at + 5 + byte_count) {
    return r.fail(DecodeErrorKind::BadLength, "announces " + std::to_string(byte_count) +
                                                  " value bytes, got " +
                                                  std::to_string(p.size() - at - 5));
  }
  if (auto e = r.reachable(start, count)) {
    return *e;
  }
  return Write{static_cast<std::uint16_t>(start * kRegisterBytes),
               table_order(std::span(p).subspan(at + 5, byte_count))};
}

template <class T>
Decoded as_instruction(DecodeResult<T>&& result) {
  if (auto* e = std::get_if<DecodeError>(&result)) {
    return std::move(*e);
  }
  return Instruction{std::get<T>(std::move(result))};
}

Decoded decode_write_multiple(const Request& r) {
  if (r.frame.params.size() < 5) {
    return r.fail(DecodeErrorKind::BadLength, "needs start, quantity and byte count, got " +
                                                  std::to_string(r.frame.params.size()) +
                                                  " data bytes");
  }
  return as_instruction(decode_values(r, 0, kMaxWriteRegisters));
}

Decoded decode_read_write(const Request& r) {
  if (r.frame.params.size() < 9) {
    return r.fail(DecodeErrorKind::BadLength,
                  "needs read start and quantity, write start, quantity and byte count, got " +
                      std::to_string(r.frame.params.size()) + " data bytes");
  }
  const std::uint16_t start = be16(r.frame.params, 0);
  const std::uint16_t count = be16(r.frame.params, 2);
  if (auto e = r.quantity(count, kMaxReadRegisters, "read quantity")) {
    return *e;
  }
  auto write = decode_values(r, 4, kMaxReadWriteWriteRegisters);
  if (auto* e = std::get_if<DecodeError>(&write)) {
    return std::move(*e);
  }
  if (auto e = r.reachable(start, count)) {
    return *e;
  }
  return WriteRead{std::get<Write>(std::move(write)), read_of(start, count)};
}

Decoded decode_diagnostics(const Request& r) {
  if (r.frame.params.size() < 2) {
    return r.fail(DecodeErrorKind::BadLength, "needs a sub-function");
  }
  // Return Query Data is the one sub-function a DYNAMIXEL server is taken to serve; any other
  // is a function it does not serve (docs/modbus.md).
  if (be16(r.frame.params, 0) != kReturnQueryData) {
    return UnknownInstruction{r.frame.instruction, r.frame.params};
  }
  return Echo{{r.frame.params.begin() + 2, r.frame.params.end()}};
}

using ModbusDecodeFn = Decoded (*)(const Request&);

struct Entry {
  ModbusFunction code;
  ModbusDecodeFn decode;
};

constexpr std::array kModbusDecoders = {
    Entry{ModbusFunction::ReadHoldingRegisters, decode_read},
    Entry{ModbusFunction::ReadInputRegisters, decode_read},
    Entry{ModbusFunction::WriteSingleRegister, decode_write_single},
    Entry{ModbusFunction::Diagnostics, decode_diagnostics},
    Entry{ModbusFunction::WriteMultipleRegisters, decode_write_multiple},
    Entry{ModbusFunction::ReadWriteMultipleRegisters, decode_read_write},
};

void append_crc(std::vector<std::uint8_t>& frame) {
  const std::uint16_t crc = crc16_modbus(frame);
  frame.push_back(static_cast<std::uint8_t>(crc & 0xFFU));
  frame.push_back(static_cast<std::uint8_t>(crc >> 8));
}

}  // namespace

DecodeResult<InstructionPacket> decode_modbus_request(const Frame& frame) {
  const Request r{frame, instruction_name(frame.protocol, frame.instruction)};
  Decoded decoded = UnknownInstruction{frame.instruction, frame.params};
  for (const Entry& entry : kModbusDecoders) {
    if (to_byte(entry.code) == frame.instruction) {
      decoded = entry.decode(r);
      break;
    }
  }
  if (auto* error = std::get_if<DecodeError>(&decoded)) {
    return std::move(*error);
  }
  return InstructionPacket{frame.protocol, frame.id, std::get<Instruction>(std::move(decoded))};
}

std::optional<std::vector<std::uint8_t>> registers_read(std::span<const std::uint8_t> data) {
  if (data.empty() || data[0] % kRegisterBytes != 0 || data.size() != 1U + data[0]) {
    return std::nullopt;
  }
  return table_order(data.subspan(1));
}

DecodeResult<ModbusResponse> decode_modbus_response(const Frame& frame) {
  const auto fail = [&](const std::string& rule) {
    return DecodeError{DecodeErrorKind::NotStatus, frame.id, frame.instruction,
                       "Modbus response " + rule};
  };
  ModbusResponse out{
      frame.id, static_cast<std::uint8_t>(frame.instruction & ~kExceptionBit), 0, {}};
  const std::vector<std::uint8_t>& p = frame.params;
  if ((frame.instruction & kExceptionBit) != 0) {
    if (p.size() != 1) {
      return fail("with an exception carries one byte, got " + std::to_string(p.size()));
    }
    out.exception = p[0];
    return out;
  }
  const auto served = std::find_if(kModbusDecoders.begin(), kModbusDecoders.end(),
                                   [&](const Entry& e) { return to_byte(e.code) == out.function; });
  if (served == kModbusDecoders.end()) {
    return fail("to function " + std::to_string(out.function) + ", which no server here serves");
  }
  const bool reads = served->code == ModbusFunction::ReadHoldingRegisters ||
                     served->code == ModbusFunction::ReadInputRegisters ||
                     served->code == ModbusFunction::ReadWriteMultipleRegisters;
  if (!reads) {
    out.data = p;
    return out;
  }
  auto bytes = registers_read(p);
  if (!bytes) {
    return fail("to a read needs a byte count and that many bytes of whole registers, got " +
                std::to_string(p.size()) + " data bytes");
  }
  out.data = std::move(*bytes);
  return out;
}

StatusPacket decode_modbus_status(const Frame& frame) {
  const bool exception = (frame.instruction & kExceptionBit) != 0 && !frame.params.empty();
  return StatusPacket{frame.protocol, frame.id, exception ? frame.params.front() : std::uint8_t{0},
                      exception ? std::vector<std::uint8_t>{} : frame.params};
}

std::vector<std::uint8_t> encode_modbus_frame(std::uint8_t address, std::uint8_t function,
                                              std::span<const std::uint8_t> data) {
  // Sized once and copied into: g++ 12 at -O3 warns (-Warray-bounds) about its own inlined
  // insert after a two-byte initialiser list.
  std::vector<std::uint8_t> frame(2 + data.size());
  frame[0] = address;
  frame[1] = function;
  std::copy(data.begin(), data.end(), frame.begin() + 2);
  append_crc(frame);
  return frame;
}

std::optional<std::uint8_t> modbus_function_of(const Instruction& instruction) {
  return std::visit(
      [](const auto& ins) -> std::optional<std::uint8_t> {
        using T = std::decay_t<decltype(ins)>;
        if constexpr (std::is_same_v<T, Read>) {
          return to_byte(ModbusFunction::ReadHoldingRegisters);
        } else if constexpr (std::is_same_v<T, Write>) {
          return to_byte(ins.data.size() == kRegisterBytes
                             ? ModbusFunction::WriteSingleRegister
                             : ModbusFunction::WriteMultipleRegisters);
        } else if constexpr (std::is_same_v<T, WriteRead>) {
          return to_byte(ModbusFunction::ReadWriteMultipleRegisters);
        } else if constexpr (std::is_same_v<T, Echo>) {
          return to_byte(ModbusFunction::Diagnostics);
        } else if constexpr (std::is_same_v<T, UnknownInstruction>) {
          return ins.instruction;
        } else {
          return std::nullopt;
        }
      },
      instruction);
}

std::vector<std::uint8_t> encode_modbus_request(const InstructionPacket& packet) {
  const auto function = modbus_function_of(packet.instruction);
  if (!function) {
    throw std::invalid_argument("Modbus RTU has no function for this instruction");
  }
  const auto whole = [](std::uint16_t address, std::size_t bytes) {
    if (address % kRegisterBytes != 0 || bytes % kRegisterBytes != 0 || bytes == 0) {
      throw std::invalid_argument("Modbus RTU reads and writes whole registers: address " +
                                  std::to_string(address) + ", " + std::to_string(bytes) +
                                  " bytes");
    }
  };
  std::vector<std::uint8_t> data;
  const auto values = [&](const Write& w) {
    whole(w.address, w.data.size());
    put_be16(data, static_cast<std::uint16_t>(w.address / kRegisterBytes));
    put_be16(data, static_cast<std::uint16_t>(w.data.size() / kRegisterBytes));
    data.push_back(static_cast<std::uint8_t>(w.data.size()));
    const std::vector<std::uint8_t> wire_order = table_order(w.data);
    data.insert(data.end(), wire_order.begin(), wire_order.end());
  };
  const auto registers = [&](const Read& r) {
    whole(r.address, r.length);
    put_be16(data, static_cast<std::uint16_t>(r.address / kRegisterBytes));
    put_be16(data, static_cast<std::uint16_t>(r.length / kRegisterBytes));
  };
  std::visit(
      [&](const auto& ins) {
        using T = std::decay_t<decltype(ins)>;
        if constexpr (std::is_same_v<T, Read>) {
          registers(ins);
        } else if constexpr (std::is_same_v<T, Write>) {
          if (*function == to_byte(ModbusFunction::WriteSingleRegister)) {
            whole(ins.address, ins.data.size());
            put_be16(data, static_cast<std::uint16_t>(ins.address / kRegisterBytes));
            const std::vector<std::uint8_t> wire_order = table_order(ins.data);
            data.insert(data.end(), wire_order.begin(), wire_order.end());
          } else {
            values(ins);
          }
        } else if constexpr (std::is_same_v<T, WriteRead>) {
          registers(ins.read);
          values(ins.write);
        } else if constexpr (std::is_same_v<T, Echo>) {
          put_be16(data, kReturnQueryData);
          data.insert(data.end(), ins.data.begin(), ins.data.end());
        } else if constexpr (std::is_same_v<T, UnknownInstruction>) {
          data = ins.params;
        }
      },
      packet.instruction);
  return encode_modbus_frame(packet.id, *function, data);
}

std::vector<std::uint8_t> encode_modbus_response(std::uint8_t address, std::uint8_t function,
                                                 const Instruction* request, std::uint8_t exception,
                                                 std::span<const std::uint8_t> table_bytes) {
  std::vector<std::uint8_t> data;
  if (exception != 0 || request == nullptr) {
    const std::uint8_t code = exception != 0 ? exception : 0x04;  // no request: device failure
    data.push_back(code);
    return encode_modbus_frame(static_cast<std::uint8_t>(address),
                               static_cast<std::uint8_t>(function | kExceptionBit), data);
  }
  const auto registers = [&] {
    data.push_back(static_cast<std::uint8_t>(table_bytes.size()));
    const std::vector<std::uint8_t> wire_order = table_order(table_bytes);
    data.insert(data.end(), wire_order.begin(), wire_order.end());
  };
  std::visit(
      [&](const auto& ins) {
        using T = std::decay_t<decltype(ins)>;
        if constexpr (std::is_same_v<T, Write>) {
          put_be16(data, static_cast<std::uint16_t>(ins.address / kRegisterBytes));
          if (function == to_byte(ModbusFunction::WriteSingleRegister)) {
            const std::vector<std::uint8_t> value = table_order(ins.data);
            data.insert(data.end(), value.begin(), value.end());
          } else {
            put_be16(data, static_cast<std::uint16_t>(ins.data.size() / kRegisterBytes));
          }
        } else if constexpr (std::is_same_v<T, Echo>) {
          put_be16(data, kReturnQueryData);
          data.insert(data.end(), ins.data.begin(), ins.data.end());
        } else {
          registers();  // Read, WriteRead
        }
      },
      *request);
  return encode_modbus_frame(address, function, data);
}

}  // namespace dxlemu::wire
