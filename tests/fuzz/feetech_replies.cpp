#include "feetech_replies.hpp"

#include <algorithm>
#include <chrono>
#include <functional>
#include <variant>

#include "fuzz_require.hpp"
#include "model/servo.hpp"
#include "wire/framer.hpp"
#include "wire/instruction_decoder.hpp"
#include "wire/status_error.hpp"

namespace dxlemu::fuzz {

namespace {

using wire::FeetechInstructionCode;

// docs/feetech.md "Response level": level 0 answers READ, PING and SYNC READ only.
constexpr std::string_view kResponseLevelKey = "response_status_level";

bool is(std::uint8_t code, FeetechInstructionCode expected) {
  return code == wire::to_byte(expected);
}

// The status bits a servo's protection model sets while a condition lasts (docs/feetech.md
// "Status bits"): voltage and overheat on every series, load except on HLS. The angle sensor and
// current bits come from injected faults only, and this bus has none.
std::uint8_t protection_bits(const model::Servo& servo) {
  std::uint8_t bits = wire::feetech_error::kVoltage | wire::feetech_error::kOverheat;
  if (servo.spec().family != model::Family::Hls) {
    bits |= wire::feetech_error::kOverload;
  }
  return bits;
}

bool answers_everything(const model::Servo& servo) {
  const auto level = servo.spec().index_of(kResponseLevelKey);
  return !level || servo.table().get(*level) != 0;
}

// docs/feetech.md "Refusals" (every shipped FEETECH model keeps its family's answers): a read
// reaching past the model's last item gets no status, whole or in part.
bool within_table(const model::Servo& servo, std::uint16_t address, std::uint16_t length) {
  return std::size_t{address} + length <= servo.spec().table_size();
}

// Position calibration is an instruction of the models with a Position offset only; to the
// others (SCS) it is unknown, and unknown instructions get no status.
bool calibrates(const model::Servo& servo) {
  return servo.spec().index_of("position_offset").has_value();
}

// The packet `bytes` holds when it is exactly one FEETECH status, nothing before or after it.
std::optional<wire::StatusPacket> one_status(std::span<const std::uint8_t> bytes) {
  wire::Framer framer(wire::Protocol::Feetech);
  std::vector<wire::FramerEvent> events;
  framer.feed(bytes, sim::SimTime{}, events);
  framer.expire(sim::SimTime{} + std::chrono::hours(1), events);
  if (events.size() != 1 || !std::holds_alternative<wire::Frame>(events.front())) {
    return std::nullopt;
  }
  const auto& frame = std::get<wire::Frame>(events.front());
  if (!std::equal(bytes.begin(), bytes.end(), frame.raw.begin(), frame.raw.end())) {
    return std::nullopt;
  }
  const auto decoded = wire::decode_status(frame);
  if (const auto* status = std::get_if<wire::StatusPacket>(&decoded)) {
    return *status;
  }
  return std::nullopt;
}

}  // namespace

void FeetechReplies::heard(const wire::FramerEvent& event, const bus::Bus& bus) {
  answers_.clear();
  next_ = 0;
  protection_bits_.clear();
  for (const auto& servo : bus.servos()) {
    protection_bits_[servo->id()] |= protection_bits(*servo);
  }
  if (const auto* frame = std::get_if<wire::Frame>(&event)) {
    after_ = frame->last_byte_at;
    expect_frame(*frame, bus);
    return;
  }
  // A damaged packet gets no status: FEETECH's error byte has no checksum bit to say so.
  after_ = std::get<wire::FramingError>(event).at;
}

void FeetechReplies::expect_frame(const wire::Frame& frame, const bus::Bus& bus) {
  const auto decoded = wire::decode_instruction(frame);
  const auto* packet = std::get_if<wire::InstructionPacket>(&decoded);
  const std::uint8_t code = frame.instruction;
  const auto everyone = [](const model::Servo& /*servo*/) { return true; };
  if (frame.id == wire::kBroadcastId) {
    if (packet == nullptr) {
      return;  // nothing broadcast is answered but PING and SYNC READ, malformed ones not at all
    }
    if (std::holds_alternative<wire::Ping>(packet->instruction)) {
      // Every servo answers at once; several collide in one slot.
      answers_.push_back({wire::kBroadcastId, bus.servos().size(), 0});
    } else if (const auto* sync = std::get_if<wire::SyncRead>(&packet->instruction)) {
      // One status per listed ID (its first listing), each after the one before; the chain stops
      // at the first listed ID nobody answers: nobody has it, or its read reaches outside the
      // tables of all who have. Response level 0 answers it too.
      const auto reads = [&](const model::Servo& servo) {
        return within_table(servo, sync->address, sync->length);
      };
      std::vector<std::uint8_t> listed;
      for (const std::uint8_t id : sync->ids) {
        if (std::find(listed.begin(), listed.end(), id) != listed.end()) {
          continue;
        }
        listed.push_back(id);
        const std::size_t n = servos_with(id, bus, true, reads);
        if (n == 0) {
          break;
        }
        answers_.push_back({id, n, sync->length});
      }
    }
    return;
  }
  // SYNC READ and SYNC WRITE are heard from 0xFE only, and Restart sends no status.
  if (is(code, FeetechInstructionCode::SyncRead) || is(code, FeetechInstructionCode::SyncWrite) ||
      (packet != nullptr && std::holds_alternative<wire::Reboot>(packet->instruction))) {
    return;
  }
  const bool read_or_ping =
      is(code, FeetechInstructionCode::Read) || is(code, FeetechInstructionCode::Ping);
  if (packet == nullptr) {
    // Parameters that do not make the instruction: no status. A READ of 0 bytes is a value the
    // servo refuses, which it acknowledges with no data, as a refused write.
    const auto& error = std::get<wire::DecodeError>(decoded);
    if (error.kind == wire::DecodeErrorKind::BadValue) {
      if (const std::size_t n = servos_with(frame.id, bus, read_or_ping, everyone); n > 0) {
        answers_.push_back({frame.id, n, 0});
      }
    }
    return;
  }
  if (std::holds_alternative<wire::UnknownInstruction>(packet->instruction)) {
    return;
  }
  std::size_t n = 0;
  std::uint16_t read_length = 0;
  if (const auto* read = std::get_if<wire::Read>(&packet->instruction)) {
    read_length = read->length;
    n = servos_with(frame.id, bus, true, [&](const model::Servo& servo) {
      return within_table(servo, read->address, read->length);
    });
  } else if (std::holds_alternative<wire::PositionCalibration>(packet->instruction)) {
    n = servos_with(frame.id, bus, false, calibrates);
  } else {
    n = servos_with(frame.id, bus, read_or_ping, everyone);
  }
  if (n > 0) {
    answers_.push_back({frame.id, n, read_length});
  }
}

std::size_t FeetechReplies::servos_with(
    std::uint8_t id, const bus::Bus& bus, bool answered_at_level_0,
    const std::function<bool(const model::Servo&)>& answers) const {
  return static_cast<std::size_t>(
      std::count_if(bus.servos().begin(), bus.servos().end(), [&](const auto& servo) {
        return servo->id() == id && (answered_at_level_0 || answers_everything(*servo)) &&
               answers(*servo);
      }));
}

bool FeetechReplies::check(std::span<const std::uint8_t> bytes, sim::SimTime at,
                           bool conflict_pending) {
  FUZZ_REQUIRE_MSG(
      next_<answers_.size(),
            "FEETECH delivery of %zu bytes (ID byte %d) when no answer is due (%zu of %zu "
            "answers sent)",
            bytes.size(), bytes.size()> 2
          ? bytes[2]
          : -1,
      next_, answers_.size());
  FUZZ_REQUIRE_MSG(at > after_, "FEETECH delivery no later than what it answers");
  after_ = at;
  const Answer& answer = answers_[next_++];
  if (matches(answer, bytes)) {
    return false;
  }
  // Otherwise only servos sharing the answer's slot, all sending at once, explain it: the AND of
  // their statuses keeps the header and, where they share one ID, that ID.
  FUZZ_REQUIRE_MSG(answer.senders > 1 && conflict_pending,
                   "FEETECH delivery of %zu bytes (ID byte %d) is not the status due from ID %u",
                   bytes.size(), bytes.size() > 2 ? bytes[2] : -1, unsigned{answer.id});
  FUZZ_REQUIRE(bytes.size() > 2 && bytes[0] == 0xFF && bytes[1] == 0xFF);
  FUZZ_REQUIRE(answer.id == wire::kBroadcastId || bytes[2] == answer.id);
  return true;
}

bool FeetechReplies::matches(const Answer& answer, std::span<const std::uint8_t> bytes) const {
  const auto status = one_status(bytes);
  if (!status) {
    return false;
  }
  const auto bits = protection_bits_.find(status->id);
  if (bits == protection_bits_.end() ||
      (answer.id != wire::kBroadcastId && status->id != answer.id)) {
    return false;
  }
  // A read the servo answers is one within its table: all its data comes. No refusal sets a bit.
  return status->params.size() == answer.read_length && (status->error & ~bits->second) == 0;
}

}  // namespace dxlemu::fuzz
