#include "modbus_replies.hpp"

#include <algorithm>
#include <variant>

#include "fuzz_require.hpp"
#include "wire/crc16_modbus.hpp"
#include "wire/modbus_codec.hpp"
#include "wire/protocol.hpp"

namespace dxlemu::fuzz {

namespace modbus_replies {

constexpr std::uint8_t kExceptionBit = 0x80;
constexpr std::uint8_t kIllegalFunction = 0x01;
constexpr std::uint8_t kLastExceptionCode = 0x04;
constexpr std::size_t kExceptionBytes = 5;  // address, function | 0x80, code, CRC
constexpr std::size_t kReadHead = 3;        // address, function, byte count
constexpr std::size_t kCrcBytes = 2;
constexpr std::size_t kWriteMultipleReply = 8;  // address, function, start, quantity, CRC
constexpr std::size_t kWriteMultipleEcho = 6;   // the part of the request it echoes

bool crc_ok(std::span<const std::uint8_t> bytes) {
  // A frame with its CRC appended (low byte first) checks to 0.
  return bytes.size() >= kCrcBytes && wire::crc16_modbus(bytes) == 0;
}

}  // namespace modbus_replies

void ModbusReplies::heard(const wire::FramerEvent& event, const bus::Bus& bus) {
  request_.reset();
  decoded_.reset();
  senders_ = 0;
  const auto* frame = std::get_if<wire::Frame>(&event);
  if (frame == nullptr || frame->protocol != wire::Protocol::Modbus ||
      frame->id == wire::kModbusBroadcastAddress) {
    return;
  }
  senders_ = static_cast<std::size_t>(
      std::count_if(bus.servos().begin(), bus.servos().end(), [&](const auto& servo) {
        return servo->id() == frame->id && servo->protocol() == wire::Protocol::Modbus;
      }));
  if (senders_ > 0) {
    request_ = *frame;
    decoded_ = wire::decode_modbus_request(*frame);
  }
}

bool ModbusReplies::check(std::span<const std::uint8_t> bytes, sim::SimTime at,
                          bool conflict_pending) {
  FUZZ_REQUIRE_MSG(request_.has_value(),
                   "a Modbus delivery of %zu bytes answers no request a servo could answer",
                   bytes.size());
  const wire::Frame& request = *request_;
  FUZZ_REQUIRE(at >= request.last_byte_at);
  // docs/modbus.md: a servo speaking Modbus has an address 1 ~ 247, whatever its ID was before.
  FUZZ_REQUIRE_MSG(request.id >= wire::kMinModbusAddress && request.id <= wire::kMaxModbusAddress,
                   "a Modbus delivery from address %u", unsigned{request.id});
  const bool well_formed = normal_response(bytes) || exception_response(bytes);
  if (!well_formed) {
    // Servos sharing the address answer at once: the AND of their frames keeps the address.
    FUZZ_REQUIRE_MSG(conflict_pending && senders_ > 1,
                     "malformed Modbus delivery of %zu bytes to function 0x%02X from address %u",
                     bytes.size(), unsigned{request.instruction}, unsigned{request.id});
    FUZZ_REQUIRE(!bytes.empty() && bytes[0] == request.id);
  }
  request_.reset();  // one answer per request
  return !well_formed;
}

bool ModbusReplies::normal_response(std::span<const std::uint8_t> bytes) const {
  using namespace modbus_replies;
  const auto* packet = std::get_if<wire::InstructionPacket>(&*decoded_);
  if (packet == nullptr || !crc_ok(bytes) || bytes.size() < kReadHead + kCrcBytes ||
      bytes[0] != request_->id || bytes[1] != request_->instruction) {
    return false;
  }
  const std::span<const std::uint8_t> raw(request_->raw);
  const wire::Instruction& ins = packet->instruction;
  const auto read_length = [&](std::uint16_t length) {
    return bytes[2] == length && bytes.size() == kReadHead + length + kCrcBytes;
  };
  if (const auto* read = std::get_if<wire::Read>(&ins)) {
    return read_length(read->length);
  }
  if (const auto* write_read = std::get_if<wire::WriteRead>(&ins)) {
    return read_length(write_read->read.length);
  }
  if (std::holds_alternative<wire::Echo>(ins) ||
      (std::holds_alternative<wire::Write>(ins) &&
       request_->instruction == wire::to_byte(wire::ModbusFunction::WriteSingleRegister))) {
    return std::equal(bytes.begin(), bytes.end(), raw.begin(), raw.end());
  }
  if (std::holds_alternative<wire::Write>(ins)) {
    return bytes.size() == kWriteMultipleReply &&
           std::equal(bytes.begin(), bytes.begin() + kWriteMultipleEcho, raw.begin());
  }
  return false;  // a function the servers do not serve has no normal response
}

bool ModbusReplies::exception_response(std::span<const std::uint8_t> bytes) const {
  using namespace modbus_replies;
  if (bytes.size() != kExceptionBytes || !crc_ok(bytes) || bytes[0] != request_->id ||
      bytes[1] != (request_->instruction | kExceptionBit)) {
    return false;
  }
  const std::uint8_t code = bytes[2];
  const auto* packet = std::get_if<wire::InstructionPacket>(&*decoded_);
  if (packet != nullptr && std::holds_alternative<wire::UnknownInstruction>(packet->instruction)) {
    return code == kIllegalFunction;
  }
  return code >= 1 && code <= kLastExceptionCode;
}

}  // namespace dxlemu::fuzz
