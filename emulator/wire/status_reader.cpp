#include "wire/status_reader.hpp"

#include "wire/instruction_decoder.hpp"

namespace dxlemu::wire {

void StatusReader::feed(std::span<const std::uint8_t> bytes, sim::SimTime at,
                        std::vector<StatusPacket>& out) {
  events_.clear();
  framer_.feed(bytes, at, events_);
  decode(out);
}

void StatusReader::end_of_write(std::vector<StatusPacket>& out) {
  events_.clear();
  framer_.end_of_write(events_);
  decode(out);
}

void StatusReader::decode(std::vector<StatusPacket>& out) {
  for (const FramerEvent& event : events_) {
    const auto* frame = std::get_if<Frame>(&event);
    if (frame == nullptr) {
      continue;
    }
    auto status = decode_status(*frame);
    if (auto* packet = std::get_if<StatusPacket>(&status)) {
      out.push_back(std::move(*packet));
    }
  }
}

}  // namespace dxlemu::wire
