#include "wire/describe.hpp"

#include <span>
#include <type_traits>

#include "wire/hex.hpp"
#include "wire/instruction_encoder.hpp"

namespace dxlemu::wire {
namespace {

std::string hex_byte(std::uint8_t b) {
  return "0x" + to_hex(std::span(&b, 1));
}

struct Describer {
  std::string& out;

  void field(const char* key, unsigned value) const {
    out += ' ';
    out += key;
    out += '=';
    out += std::to_string(value);
  }
  void data(const std::vector<std::uint8_t>& bytes) const {
    out += " data=";
    out += to_hex(bytes);
  }

  void operator()(const Ping&) const {}
  void operator()(const Action&) const {}
  void operator()(const Reboot&) const {}
  void operator()(const Read& r) const {
    field("address", r.address);
    field("length", r.length);
  }
  void operator()(const Write& w) const {
    field("address", w.address);
    data(w.data);
  }
  void operator()(const RegWrite& w) const {
    field("address", w.address);
    data(w.data);
  }
  void operator()(const FactoryReset& f) const { out += " option=" + hex_byte(f.option); }
  void operator()(const Clear& c) const { option_and_data(c.option, c.data); }
  void operator()(const ControlTableBackup& c) const { option_and_data(c.option, c.data); }
  void operator()(const SyncRead& r) const {
    field("address", r.address);
    field("length", r.length);
    out += " ids=";
    for (std::size_t i = 0; i < r.ids.size(); ++i) {
      if (i != 0) {
        out += ' ';
      }
      out += std::to_string(r.ids[i]);
    }
  }
  void operator()(const SyncWrite& s) const {
    field("address", s.address);
    field("length", s.length);
    for (const SyncWriteTarget& t : s.targets) {
      out += " [" + std::to_string(t.id) + ": " + to_hex(t.data) + "]";
    }
  }
  void operator()(const BulkRead& r) const {
    for (const BulkReadTarget& t : r.targets) {
      out += " [" + std::to_string(t.id) + ":";
      field("address", t.address);
      field("length", t.length);
      out += "]";
    }
  }
  void operator()(const BulkWrite& b) const {
    for (const BulkWriteTarget& t : b.targets) {
      out += " [" + std::to_string(t.id) + ":";
      field("address", t.address);
      data(t.data);
      out += "]";
    }
  }
  void operator()(const ParameterRecovery&) const {}
  void operator()(const ParameterBackup&) const {}
  void operator()(const StatusReset&) const {}
  void operator()(const PositionCalibration& p) const {
    if (p.position) {
      field("position", *p.position);
    }
  }
  void operator()(const WriteRead& w) const {
    (*this)(w.write);
    out += ';';
    (*this)(w.read);
  }
  void operator()(const Echo& e) const { data(e.data); }
  void operator()(const UnknownInstruction& u) const {
    out += " instruction=" + hex_byte(u.instruction);
    if (!u.params.empty()) {
      out += " params=" + to_hex(u.params);
    }
  }

  void option_and_data(std::uint8_t option, const std::vector<std::uint8_t>& bytes) const {
    out += " option=" + hex_byte(option);
    if (!bytes.empty()) {
      data(bytes);
    }
  }
};

}  // namespace

std::string describe(const InstructionPacket& packet) {
  std::string out = "id=" + std::to_string(packet.id) + " ";
  // An UnknownInstruction may carry a byte that names an instruction of another protocol
  // (0x10 in 1.0); it is still unknown to this packet's protocol.
  out += std::holds_alternative<UnknownInstruction>(packet.instruction)
             ? std::string_view("unknown")
             : instruction_name(packet.protocol,
                                instruction_code(packet.protocol, packet.instruction));
  std::visit(Describer{out}, packet.instruction);
  return out;
}

std::string describe(const StatusPacket& status) {
  std::string out = "id=" + std::to_string(status.id) + " error=" + hex_byte(status.error);
  if (!status.params.empty()) {
    out += " params=" + to_hex(status.params);
  }
  return out;
}

std::string describe(const FastReply& reply) {
  std::string out = "id=" + std::to_string(kBroadcastId) + " fast_reply";
  for (const FastReplyBlock& b : reply.blocks) {
    out += " [" + std::to_string(b.id) + ": error=" + hex_byte(b.error) +
           " data=" + to_hex(b.data) + "]";
  }
  return out;
}

}  // namespace dxlemu::wire
