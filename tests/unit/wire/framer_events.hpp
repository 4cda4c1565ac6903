#pragma once

#include <catch2/catch.hpp>

#include <initializer_list>
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

/// The byte strings of `parts`, one after the other.
inline std::vector<std::uint8_t> concat(std::initializer_list<std::vector<std::uint8_t>> parts) {
  std::vector<std::uint8_t> out;
  for (const auto& p : parts) {
    out.insert(out.end(), p.begin(), p.end());
  }
  return out;
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

/// The one frame `bytes` make in a fresh framer of `protocol`, with nothing left buffered; fails
/// the test case otherwise.
inline wire::Frame frame_one(wire::Protocol protocol, const std::vector<std::uint8_t>& bytes) {
  wire::Framer framer(protocol);
  std::vector<wire::FramerEvent> events;
  framer.feed(bytes, sim::SimTime{}, events);
  INFO(summary(events));
  REQUIRE(events.size() == 1);
  REQUIRE(std::holds_alternative<wire::Frame>(events[0]));
  REQUIRE(framer.buffered() == 0);
  return std::get<wire::Frame>(events[0]);
}

}  // namespace dxlemu::test
