#include "wire/instruction_decoder.hpp"

#include <array>
#include <span>
#include <string>
#include <utility>

#include "wire/crc16.hpp"
#include "wire/hex.hpp"
#include "wire/modbus_codec.hpp"

namespace dxlemu::wire {
namespace {

// Fixed bytes that guard destructive instructions (protocol2.md "Clear" and "Control Table
// Backup").
constexpr std::array<std::uint8_t, 4> kClearMagic = {0x44, 0x58, 0x4C, 0x22};
constexpr std::array<std::uint8_t, 4> kBackupMagic = {0x43, 0x54, 0x52, 0x4C};
constexpr std::uint8_t kClearMultiTurn = 0x01;
constexpr std::uint8_t kBackupStore = 0x01;
constexpr std::uint8_t kBackupRestore = 0x02;

// Reads parameter fields in order. Address and data-length fields are 1 byte in Protocol 1.0 and
// FEETECH and 2 bytes (little-endian) in 2.0; everything else is a byte. Callers check
// remaining() first.
class ParamReader {
 public:
  ParamReader(Protocol protocol, std::span<const std::uint8_t> params)
      : protocol_(protocol), params_(params) {}

  std::size_t remaining() const { return params_.size() - pos_; }
  std::size_t field_bytes() const { return has_v1_layout(protocol_) ? 1 : 2; }
  std::uint8_t byte() { return params_[pos_++]; }
  std::uint16_t u16() {
    const auto lo = params_[pos_];
    const auto hi = params_[pos_ + 1];
    pos_ += 2;
    return static_cast<std::uint16_t>(lo | (hi << 8));
  }
  std::uint16_t field() { return has_v1_layout(protocol_) ? byte() : u16(); }
  std::vector<std::uint8_t> take(std::size_t n) {
    const auto first = params_.begin() + static_cast<std::ptrdiff_t>(pos_);
    pos_ += n;
    return {first, first + static_cast<std::ptrdiff_t>(n)};
  }

 private:
  Protocol protocol_;
  std::span<const std::uint8_t> params_;
  std::size_t pos_ = 0;
};

// What a decode function gets and how it reports failure.
struct Context {
  const Frame& frame;
  ParamReader& in;
  std::string_view name;

  DecodeError fail(DecodeErrorKind kind, std::string rule) const {
    return DecodeError{kind, frame.id, frame.instruction,
                       std::string(name) + " " + std::move(rule)};
  }
  DecodeError wrong_length(std::string layout) const {
    return fail(DecodeErrorKind::BadLength, "needs " + std::move(layout) + ", got " +
                                                std::to_string(frame.params.size()) +
                                                " parameter bytes");
  }
  bool v1() const { return frame.protocol == Protocol::V1; }
};

using Decoded = DecodeResult<Instruction>;
using DecodeFn = Decoded (*)(Context&);

std::string bytes_word(std::size_t n) {
  return std::to_string(n) + (n == 1 ? " byte" : " bytes");
}

Decoded no_params(Context& c, Instruction instruction) {
  if (c.in.remaining() != 0) {
    return c.wrong_length("no parameters");
  }
  return instruction;
}

Decoded decode_ping(Context& c) {
  return no_params(c, Ping{});
}
Decoded decode_action(Context& c) {
  return no_params(c, Action{});
}
Decoded decode_reboot(Context& c) {
  return no_params(c, Reboot{});
}

Decoded decode_read(Context& c) {
  if (c.in.remaining() != 2 * c.in.field_bytes()) {
    return c.wrong_length(bytes_word(2 * c.in.field_bytes()) + " (address, length)");
  }
  Read r;
  r.address = c.in.field();
  r.length = c.in.field();
  if (r.length == 0) {
    return c.fail(DecodeErrorKind::BadValue, "data length must be at least 1");
  }
  return r;
}

template <class WriteLike>
Decoded decode_write(Context& c) {
  if (c.in.remaining() < c.in.field_bytes() + 1) {
    return c.wrong_length("an address and at least 1 data byte");
  }
  WriteLike w;
  w.address = c.in.field();
  w.data = c.in.take(c.in.remaining());
  return w;
}

Decoded decode_factory_reset(Context& c) {
  if (c.v1()) {
    return no_params(c, FactoryReset{factory_reset::kResetAll});  // 1.0 always resets everything
  }
  if (c.in.remaining() != 1) {
    return c.wrong_length("1 byte (option)");
  }
  const std::uint8_t option = c.in.byte();
  if (option != factory_reset::kResetAll && option != factory_reset::kResetAllButId &&
      option != factory_reset::kResetAllButIdAndBaud) {
    return c.fail(DecodeErrorKind::BadValue,
                  "option must be 0xFF, 0x01 or 0x02, got 0x" + to_hex(std::span(&option, 1)));
  }
  return FactoryReset{option};
}

// Clear and Control Table Backup share a layout: an option byte, and for the defined options
// four fixed bytes that must match exactly.
template <class OptionInstruction>
Decoded decode_guarded(Context& c, std::span<const std::uint8_t> magic,
                       std::initializer_list<std::uint8_t> guarded_options) {
  if (c.in.remaining() < 1) {
    return c.wrong_length("an option byte");
  }
  OptionInstruction out;
  out.option = c.in.byte();
  out.data = c.in.take(c.in.remaining());
  for (const std::uint8_t option : guarded_options) {
    if (out.option == option &&
        !std::equal(out.data.begin(), out.data.end(), magic.begin(), magic.end())) {
      return c.fail(DecodeErrorKind::BadValue,
                    "option 0x" + to_hex(std::span(&option, 1)) + " needs the fixed bytes " +
                        to_hex(magic) + ", got " + (out.data.empty() ? "none" : to_hex(out.data)));
    }
  }
  return out;
}

Decoded decode_clear(Context& c) {
  return decode_guarded<Clear>(c, kClearMagic, {kClearMultiTurn});
}

Decoded decode_backup(Context& c) {
  return decode_guarded<ControlTableBackup>(c, kBackupMagic, {kBackupStore, kBackupRestore});
}

template <class SyncReadLike>
Decoded decode_sync_read(Context& c) {
  const std::size_t head = 2 * c.in.field_bytes();
  if (c.in.remaining() < head + 1) {
    return c.wrong_length(bytes_word(head) + " (address, length) and at least one ID");
  }
  SyncReadLike r;
  r.address = c.in.field();
  r.length = c.in.field();
  if (r.length == 0) {
    return c.fail(DecodeErrorKind::BadValue, "data length must be at least 1");
  }
  r.ids = c.in.take(c.in.remaining());
  return r;
}

Decoded decode_sync_write(Context& c) {
  const std::size_t head = 2 * c.in.field_bytes();
  if (c.in.remaining() < head) {
    return c.wrong_length(bytes_word(head) + " (address, length) and data blocks");
  }
  SyncWrite w;
  w.address = c.in.field();
  w.length = c.in.field();
  if (w.length == 0) {
    return c.fail(DecodeErrorKind::BadValue, "data length must be at least 1");
  }
  const std::size_t block = std::size_t{1} + w.length;  // ID + data
  if (c.in.remaining() == 0 || c.in.remaining() % block != 0) {
    return c.fail(DecodeErrorKind::BadLength,
                  "blocks of " + bytes_word(block) + " (ID + " + bytes_word(w.length) +
                      ") must divide the remaining " + bytes_word(c.in.remaining()));
  }
  while (c.in.remaining() > 0) {
    SyncWriteTarget t;
    t.id = c.in.byte();
    t.data = c.in.take(w.length);
    w.targets.push_back(std::move(t));
  }
  return w;
}

// protocol1.md "Bulk Read": 0x00, then [length, ID, address] per device.
Decoded decode_bulk_read_v1(Context& c) {
  constexpr std::size_t kBlock = 3;
  if (c.in.remaining() < 1 + kBlock || (c.in.remaining() - 1) % kBlock != 0) {
    return c.wrong_length("0x00 and blocks of 3 bytes (length, ID, address)");
  }
  if (c.in.byte() != kV1BulkReadLeadByte) {
    return c.fail(DecodeErrorKind::BadValue, "first parameter must be 0x00");
  }
  BulkRead r;
  while (c.in.remaining() > 0) {
    BulkReadTarget t;
    t.length = c.in.byte();
    t.id = c.in.byte();
    t.address = c.in.byte();
    if (t.length == 0) {
      return c.fail(DecodeErrorKind::BadValue, "data length must be at least 1");
    }
    r.targets.push_back(t);
  }
  return r;
}

// protocol2.md "Bulk Read (0x92)": [ID, address, length] per device, 16-bit fields.
template <class BulkReadLike>
Decoded decode_bulk_read_v2(Context& c) {
  constexpr std::size_t kBlock = 5;
  if (c.in.remaining() == 0 || c.in.remaining() % kBlock != 0) {
    return c.wrong_length("blocks of 5 bytes (ID, address, length)");
  }
  BulkReadLike r;
  while (c.in.remaining() > 0) {
    BulkReadTarget t;
    t.id = c.in.byte();
    t.address = c.in.u16();
    t.length = c.in.u16();
    if (t.length == 0) {
      return c.fail(DecodeErrorKind::BadValue, "data length must be at least 1");
    }
    r.targets.push_back(t);
  }
  return r;
}

Decoded decode_bulk_read(Context& c) {
  return c.v1() ? decode_bulk_read_v1(c) : decode_bulk_read_v2<BulkRead>(c);
}

Decoded decode_bulk_write(Context& c) {
  constexpr std::size_t kHead = 5;  // ID, address, length
  if (c.in.remaining() == 0) {
    return c.wrong_length("blocks of ID, address, length and data");
  }
  BulkWrite w;
  while (c.in.remaining() > 0) {
    if (c.in.remaining() < kHead) {
      return c.fail(DecodeErrorKind::BadLength,
                    "block " + std::to_string(w.targets.size() + 1) +
                        " is cut short: " + bytes_word(c.in.remaining()) + " left");
    }
    BulkWriteTarget t;
    t.id = c.in.byte();
    t.address = c.in.u16();
    const std::uint16_t length = c.in.u16();
    if (length == 0) {
      return c.fail(DecodeErrorKind::BadValue, "data length must be at least 1");
    }
    if (c.in.remaining() < length) {
      return c.fail(DecodeErrorKind::BadLength,
                    "block " + std::to_string(w.targets.size() + 1) + " announces " +
                        bytes_word(length) + " of data, " + bytes_word(c.in.remaining()) + " left");
    }
    t.data = c.in.take(length);
    w.targets.push_back(std::move(t));
  }
  return w;
}

// protocol-ft-scs.md 4.9: no parameter (the middle position) or the 2-byte set value, low byte
// first as in Example 11. Only STS, SMS and HLS servos, all little-endian, support it.
Decoded decode_position_calibration(Context& c) {
  if (c.in.remaining() == 0) {
    return PositionCalibration{};
  }
  if (c.in.remaining() != 2) {
    return c.wrong_length("no parameters or 2 bytes (position, low byte first)");
  }
  return PositionCalibration{c.in.u16()};
}

Decoded decode_parameter_recovery(Context& c) {
  return no_params(c, ParameterRecovery{});
}
Decoded decode_parameter_backup(Context& c) {
  return no_params(c, ParameterBackup{});
}
Decoded decode_status_reset(Context& c) {
  return no_params(c, StatusReset{});
}

// Which instructions each DYNAMIXEL protocol defines and how to decode them. Protocol 1.0 lacks
// Clear, Backup, Sync Read, Bulk Write and the Fast reads (protocol1.md "Instruction").
struct DecoderEntry {
  InstructionCode code;
  bool in_v1;
  DecodeFn decode;
};

constexpr std::array kDecoders = {
    DecoderEntry{InstructionCode::Ping, true, decode_ping},
    DecoderEntry{InstructionCode::Read, true, decode_read},
    DecoderEntry{InstructionCode::Write, true, decode_write<Write>},
    DecoderEntry{InstructionCode::RegWrite, true, decode_write<RegWrite>},
    DecoderEntry{InstructionCode::Action, true, decode_action},
    DecoderEntry{InstructionCode::FactoryReset, true, decode_factory_reset},
    DecoderEntry{InstructionCode::Reboot, true, decode_reboot},
    DecoderEntry{InstructionCode::Clear, false, decode_clear},
    DecoderEntry{InstructionCode::ControlTableBackup, false, decode_backup},
    DecoderEntry{InstructionCode::SyncRead, false, decode_sync_read<SyncRead>},
    DecoderEntry{InstructionCode::FastSyncRead, false, decode_sync_read<FastSyncRead>},
    DecoderEntry{InstructionCode::SyncWrite, true, decode_sync_write},
    DecoderEntry{InstructionCode::BulkRead, true, decode_bulk_read},
    DecoderEntry{InstructionCode::FastBulkRead, false, decode_bulk_read_v2<FastBulkRead>},
    DecoderEntry{InstructionCode::BulkWrite, false, decode_bulk_write},
};

// FEETECH's instructions (protocol-ft-scs.md 4 and sdk-constants.md). Layouts shared with 1.0 use
// the same decoders, which read one-byte address and length fields for FEETECH.
struct FeetechDecoderEntry {
  FeetechInstructionCode code;
  DecodeFn decode;
};

constexpr std::array kFeetechDecoders = {
    FeetechDecoderEntry{FeetechInstructionCode::Ping, decode_ping},
    FeetechDecoderEntry{FeetechInstructionCode::Read, decode_read},
    FeetechDecoderEntry{FeetechInstructionCode::Write, decode_write<Write>},
    FeetechDecoderEntry{FeetechInstructionCode::RegWrite, decode_write<RegWrite>},
    FeetechDecoderEntry{FeetechInstructionCode::Action, decode_action},
    FeetechDecoderEntry{FeetechInstructionCode::ParameterRecovery, decode_parameter_recovery},
    FeetechDecoderEntry{FeetechInstructionCode::Restart, decode_reboot},
    FeetechDecoderEntry{FeetechInstructionCode::ParameterBackup, decode_parameter_backup},
    FeetechDecoderEntry{FeetechInstructionCode::StatusReset, decode_status_reset},
    FeetechDecoderEntry{FeetechInstructionCode::PositionCalibration, decode_position_calibration},
    FeetechDecoderEntry{FeetechInstructionCode::SyncRead, decode_sync_read<SyncRead>},
    FeetechDecoderEntry{FeetechInstructionCode::SyncWrite, decode_sync_write},
};

// The decoder of `code` in `protocol`, or nullptr when the protocol does not define it.
DecodeFn decoder_for(Protocol protocol, std::uint8_t code) {
  if (protocol == Protocol::Feetech) {
    for (const FeetechDecoderEntry& entry : kFeetechDecoders) {
      if (to_byte(entry.code) == code) {
        return entry.decode;
      }
    }
    return nullptr;
  }
  for (const DecoderEntry& entry : kDecoders) {
    if (to_byte(entry.code) == code && (entry.in_v1 || protocol == Protocol::V2)) {
      return entry.decode;
    }
  }
  return nullptr;
}

}  // namespace

DecodeResult<InstructionPacket> decode_instruction(const Frame& frame) {
  if (frame.protocol == Protocol::Modbus) {
    return decode_modbus_request(frame);
  }
  ParamReader in(frame.protocol, frame.params);
  Context c{frame, in, instruction_name(frame.protocol, frame.instruction)};
  const auto decode = decoder_for(frame.protocol, frame.instruction);
  Decoded decoded =
      decode != nullptr ? decode(c) : Decoded{UnknownInstruction{frame.instruction, frame.params}};
  if (auto* error = std::get_if<DecodeError>(&decoded)) {
    return std::move(*error);
  }
  return InstructionPacket{frame.protocol, frame.id, std::get<Instruction>(std::move(decoded))};
}

DecodeResult<StatusPacket> decode_status(const Frame& frame) {
  if (frame.protocol == Protocol::Modbus) {
    return decode_modbus_status(frame);
  }
  if (has_v1_layout(frame.protocol)) {
    return StatusPacket{frame.protocol, frame.id, frame.instruction, frame.params};
  }
  if (frame.instruction != to_byte(InstructionCode::Status) || frame.params.empty()) {
    return DecodeError{DecodeErrorKind::NotStatus, frame.id, frame.instruction,
                       "a status packet has instruction 0x55 and an error byte"};
  }
  return StatusPacket{
      Protocol::V2, frame.id, frame.params.front(), {frame.params.begin() + 1, frame.params.end()}};
}

DecodeResult<FastReply> decode_fast_reply(const Frame& frame,
                                          std::span<const std::uint16_t> lengths) {
  auto fail = [&](DecodeErrorKind kind, std::string reason) {
    return DecodeError{kind, frame.id, frame.instruction, "fast reply " + std::move(reason)};
  };
  if (frame.protocol != Protocol::V2 || frame.id != kBroadcastId ||
      frame.instruction != to_byte(InstructionCode::Status)) {
    return fail(DecodeErrorKind::NotStatus, "must be a 2.0 status packet from ID 0xFE");
  }
  // The reply is never stuffed, so its blocks can be read from the raw packet: after the 0x55
  // come [error, ID, data, CRC_L, CRC_H] per device, where each CRC is the running CRC of the
  // packet up to that block's last data byte and the last block's CRC is the packet's CRC.
  constexpr std::size_t kBlockOverhead = 4;  // error, ID, CRC_L, CRC_H
  constexpr std::size_t kBlocksAt = 8;       // FF FF FD 00 ID LEN_L LEN_H 0x55
  std::size_t expected = 0;
  for (const std::uint16_t n : lengths) {
    expected += kBlockOverhead + n;
  }
  const std::size_t got = frame.raw.size() > kBlocksAt ? frame.raw.size() - kBlocksAt : 0;
  if (lengths.empty() || got != expected) {
    return fail(DecodeErrorKind::BadLength, "needs " + bytes_word(expected) + " for " +
                                                std::to_string(lengths.size()) + " blocks, got " +
                                                std::to_string(got));
  }
  const std::span<const std::uint8_t> raw(frame.raw);
  FastReply reply;
  std::size_t at = kBlocksAt;
  for (std::size_t i = 0; i < lengths.size(); ++i) {
    FastReplyBlock block;
    block.error = raw[at];
    block.id = raw[at + 1];
    const auto data = raw.subspan(at + 2, lengths[i]);
    block.data.assign(data.begin(), data.end());
    at += 2 + lengths[i];
    const std::uint16_t crc = crc16(raw.first(at));
    if (raw[at] != (crc & 0xFFU) || raw[at + 1] != (crc >> 8)) {
      return fail(DecodeErrorKind::BadValue, "block " + std::to_string(i + 1) + " (ID " +
                                                 std::to_string(block.id) + ") has a wrong CRC");
    }
    at += 2;
    reply.blocks.push_back(std::move(block));
  }
  return reply;
}

}  // namespace dxlemu::wire
