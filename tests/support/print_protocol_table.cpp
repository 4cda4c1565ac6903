// Prints the protocol table (wire/protocol_table.hpp) as JSON, for the test that ties its copies
// outside C++ (the Python package's codes, the Wireshark dissector's names) to it
// (tests/protocol_table/copies_test.py).
#include <chrono>
#include <cstdio>
#include <string>
#include <string_view>

#include "sim/sim_time.hpp"
#include "wire/protocol.hpp"

namespace {

using namespace dxlemu::wire;

// Appended, not `"\"" + std::string(text)`: g++ 12 at -O3 warns (-Wrestrict) about that.
std::string quoted(std::string_view text) {
  std::string out(1, '"');
  out.append(text).push_back('"');
  return out;
}

std::string_view role_name(InstructionRole role) {
  switch (role) {
    case InstructionRole::Single:
      return "single";
    case InstructionRole::GroupRead:
      return "group_read";
    case InstructionRole::GroupWrite:
      return "group_write";
    case InstructionRole::Status:
      return "status";
  }
  return "unknown";
}

std::string_view check_name(CheckKind check) {
  switch (check) {
    case CheckKind::Sum8:
      return "sum8";
    case CheckKind::Crc16Robotis:
      return "crc16_robotis";
    case CheckKind::Crc16Modbus:
      return "crc16_modbus";
  }
  return "unknown";
}

std::string_view shape_name(StatusShape shape) {
  switch (shape) {
    case StatusShape::ErrorNumber:
      return "error_number";
    case StatusShape::ErrorBits:
      return "error_bits";
    case StatusShape::DeviceStatus:
      return "device_status";
    case StatusShape::ExceptionCode:
      return "exception_code";
  }
  return "unknown";
}

std::string_view delimiting_name(Delimiting delimiting) {
  switch (delimiting) {
    case Delimiting::LengthField:
      return "length_field";
    case Delimiting::Silence:
      return "silence";
  }
  return "unknown";
}

std::string microseconds(dxlemu::sim::SimDuration duration) {
  return std::to_string(std::chrono::duration_cast<std::chrono::microseconds>(duration).count());
}

std::string row_json(const ProtocolTraits& row) {
  std::string out = "{";
  out += "\"value\": " + std::to_string(static_cast<int>(row.protocol));
  out += ", \"name\": " + quoted(row.name) + ", \"title\": " + quoted(row.title);
  out += ", \"spelling\": " + quoted(row.spelling) + ", \"number\": " + std::to_string(row.number);
  out += ", \"type_value\": " + std::to_string(row.type_value);
  out += ", \"maker\": " + quoted(row.maker);
  out += ", \"min_unicast_id\": " + std::to_string(row.min_unicast_id);
  out += ", \"max_unicast_id\": " + std::to_string(row.max_unicast_id);
  out += ", \"broadcast_id\": " + std::to_string(row.broadcast_id);
  out += ", \"header\": [";
  for (std::size_t i = 0; i < row.frame.header_size; ++i) {
    out += (i == 0 ? "" : ", ") + std::to_string(row.frame.header[i]);
  }
  out += "], \"field_bytes\": " + std::to_string(row.frame.field_bytes);
  out += ", \"min_length\": " + std::to_string(row.frame.min_length);
  out += ", \"max_length\": " + std::to_string(row.frame.max_length);
  out += ", \"check\": " + quoted(check_name(row.frame.check));
  out += ", \"stuffing\": " + std::string(row.frame.stuffing ? "true" : "false");
  out += ", \"inter_byte_timeout_us\": " + microseconds(row.frame.inter_byte_timeout);
  out += ", \"delimiting\": " + quoted(delimiting_name(row.frame.delimiting));
  out += ", \"silence_tenths\": " + std::to_string(row.frame.silence_tenths);
  out += ", \"gap_tenths\": " + std::to_string(row.frame.gap_tenths);
  out += ", \"char_bits\": " + std::to_string(row.frame.char_bits);
  out += ", \"fixed_timing_above_bps\": " + std::to_string(row.frame.fixed_timing_above_bps);
  out += ", \"fixed_silence_us\": " + microseconds(row.frame.fixed_silence);
  out += ", \"fixed_gap_us\": " + microseconds(row.frame.fixed_gap);
  out += ", \"status_shape\": " + quoted(shape_name(row.status.shape));
  out += ", \"alert_bit\": " + std::to_string(row.status.alert_bit);
  out += ", \"register_bytes\": " + std::to_string(row.register_bytes);
  // The code of every outcome (indexed by wire::Outcome): for Modbus, the exception codes the
  // emulator can send, which the copies must name.
  out += ", \"status_codes\": [";
  for (std::size_t i = 0; i < row.status.code.size(); ++i) {
    out += (i == 0 ? "" : ", ") + std::to_string(row.status.code[i]);
  }
  out += "]";
  out += ", \"instructions\": [";
  bool first = true;
  for (const InstructionInfo& info : row.instructions) {
    out += first ? "" : ", ";
    first = false;
    out += "{\"code\": " + std::to_string(info.code) + ", \"name\": " + quoted(info.name) +
           ", \"title\": " + quoted(info.title) + ", \"role\": " + quoted(role_name(info.role)) +
           "}";
  }
  return out + "]}";
}

}  // namespace

int main() {
  std::string out = "[";
  for (const ProtocolTraits& row : kProtocolTable) {
    out += (out.size() == 1 ? "\n  " : ",\n  ") + row_json(row);
  }
  out += "\n]\n";
  std::fputs(out.c_str(), stdout);
  return 0;
}
