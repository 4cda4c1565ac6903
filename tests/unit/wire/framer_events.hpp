#pragma once

#include <string>
#include <variant>
#include <vector>

#include "wire/frame.hpp"
#include "wire/framer.hpp"
#include "wire/instruction_encoder.hpp"

namespace dxlemu::test {

/// A Ping instruction packet to `id` in `protocol`: the shortest valid packet, for framing tests.
inline std::vector<std::uint8_t> ping_packet(wire::Protocol protocol, std::uint8_t id) {
  return wire::encode_instruction({protocol, id, wire::Ping{}});
}

/// The frames among framer events, in order.
inline std::vector<wire::Frame> frames_of(const std::vector<wire::FramerEvent>& events) {
  std::vector<wire::Frame> out;
  for (const auto& e : events) {
    if (const auto* f = std::get_if<wire::Frame>(&e)) {
      out.push_back(*f);
    }
  }
  return out;
}

/// The framing errors among framer events, in order.
inline std::vector<wire::FramingError> errors_of(const std::vector<wire::FramerEvent>& events) {
  std::vector<wire::FramingError> out;
  for (const auto& e : events) {
    if (const auto* f = std::get_if<wire::FramingError>(&e)) {
      out.push_back(*f);
    }
  }
  return out;
}

/// A compact picture of an event sequence for assertions: "frame(id=1) garbage(3) bad_check(id=2)".
inline std::string summary(const std::vector<wire::FramerEvent>& events) {
  std::string out;
  for (const auto& e : events) {
    if (!out.empty()) {
      out += ' ';
    }
    if (const auto* f = std::get_if<wire::Frame>(&e)) {
      out += "frame(id=" + std::to_string(f->id) + ")";
      continue;
    }
    const auto& err = std::get<wire::FramingError>(e);
    switch (err.kind) {
      case wire::FramingErrorKind::Garbage:
        out += "garbage(" + std::to_string(err.bytes) + ")";
        break;
      case wire::FramingErrorKind::BadCheck:
        out += "bad_check(id=" + std::to_string(err.id.value_or(0)) + ")";
        break;
      case wire::FramingErrorKind::ImpossibleLength:
        out += "impossible_length(id=" + std::to_string(err.id.value_or(0)) + ")";
        break;
      case wire::FramingErrorKind::Truncated:
        out += "truncated(" + std::to_string(err.bytes) + ")";
        break;
    }
  }
  return out;
}

}  // namespace dxlemu::test
