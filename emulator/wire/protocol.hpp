#pragma once

// The questions the rest of the emulator asks about a protocol, each answered from its row in
// the protocol table (wire/protocol_table.hpp).

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "wire/protocol_codes.hpp"
#include "wire/protocol_table.hpp"

namespace dxlemu::wire {

/// The protocol as users write it: "1.0", "2.0" or "feetech".
constexpr std::string_view protocol_name(Protocol protocol) {
  return traits(protocol).name;
}

/// The protocol in messages: "Protocol 1.0", "Protocol 2.0" or "FEETECH".
constexpr std::string_view protocol_title(Protocol protocol) {
  return traits(protocol).title;
}

/// The protocol's number where it has one: DYNAMIXEL's 1 and 2 (as the Protocol Type item and
/// the JSON of traces, configs and the control API write them); 0 for FEETECH, which JSON names
/// "feetech" (protocol_name) instead.
constexpr int protocol_number(Protocol protocol) {
  return traits(protocol).number;
}

/// The protocol as JSON writes it: its number, or its quoted spelling when it has none.
inline std::string protocol_json_text(Protocol protocol) {
  const ProtocolTraits& row = traits(protocol);
  if (row.number != 0) {
    return std::to_string(row.number);
  }
  // Appended, not `"\"" + std::string(...)`: g++ 12 at -O3 warns (-Wrestrict) about its own
  // inlined insert there.
  std::string quoted(1, '"');
  quoted.append(row.spelling).push_back('"');
  return quoted;
}

/// Every protocol as JSON writes it, in table order, separated by ", ": `1, 2, "feetech"`.
inline std::string protocol_json_list() {
  std::string out;
  for (const ProtocolTraits& row : kProtocolTable) {
    if (!out.empty()) {
      out += ", ";
    }
    out += protocol_json_text(row.protocol);
  }
  return out;
}

/// Every protocol's spelling, in table order: "1", "2", "feetech" (the CLI's choices).
inline std::vector<std::string> protocol_spellings() {
  std::vector<std::string> out;
  out.reserve(std::size(kProtocolTable));
  for (const ProtocolTraits& row : kProtocolTable) {
    out.emplace_back(row.spelling);
  }
  return out;
}

/// Every protocol, in table order.
inline std::vector<Protocol> all_protocols() {
  std::vector<Protocol> out;
  out.reserve(std::size(kProtocolTable));
  for (const ProtocolTraits& row : kProtocolTable) {
    out.push_back(row.protocol);
  }
  return out;
}

/// True for the protocols laid out like Protocol 1.0: header FF FF, one-byte LENGTH, one-byte
/// checksum, no stuffing, one-byte address and length fields, the error byte of a status packet
/// in the instruction position. FEETECH's FT-SCS frame is the 1.0 frame (protocol-ft-scs.md 2, 3).
constexpr bool has_v1_layout(Protocol protocol) {
  return traits(protocol).frame.field_bytes == 1;
}

/// The snake_case name of a DYNAMIXEL instruction ("sync_read"), used in traces, errors and the
/// control API; "unknown" for a byte that is not an InstructionCode.
constexpr std::string_view instruction_name(std::uint8_t code) {
  const InstructionInfo* info = instruction_info(Protocol::V2, code);
  return info != nullptr ? info->name : "unknown";
}

/// The snake_case name of a FEETECH instruction; "unknown" for a byte that is not a
/// FeetechInstructionCode. Codes with a DYNAMIXEL twin of the same meaning have its name
/// (0x08 Restart decodes as Reboot: "reboot").
constexpr std::string_view feetech_instruction_name(std::uint8_t code) {
  const InstructionInfo* info = instruction_info(Protocol::Feetech, code);
  return info != nullptr ? info->name : "unknown";
}

/// The name of instruction byte `code` in `protocol`. The DYNAMIXEL names do not depend on the
/// version: a 2.0-only code in a 1.0 packet still has its 2.0 name here.
constexpr std::string_view instruction_name(Protocol protocol, std::uint8_t code) {
  const InstructionInfo* info = instruction_info(protocol, code);
  return info != nullptr ? info->name : "unknown";
}

/// Highest unicast Packet ID of `protocol`.
constexpr std::uint8_t max_unicast_id(Protocol protocol) {
  return traits(protocol).max_unicast_id;
}

/// True when `id` may appear as a Packet ID of `protocol` (a unicast ID or the broadcast ID).
constexpr bool is_valid_packet_id(Protocol protocol, std::uint8_t id) {
  const ProtocolTraits& row = traits(protocol);
  return id == row.broadcast_id || id <= row.max_unicast_id;
}

}  // namespace dxlemu::wire
