#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>

#include "sim/sim_time.hpp"
#include "wire/frame.hpp"

namespace dxlemu::app {

/// One trace line (docs/trace.md), a JSON object without the line end, for what the framers of
/// `port` heard from the client: a packet, decoded, or a framing failure.
std::string heard_record(const std::string& port, const wire::FramerEvent& event);

/// One trace line (a JSON object) for `bytes` that `port` delivered to the client at `at`, decoded
/// as status packets of `protocol` (several packets, a Fast reply, or colliding replies). `late`,
/// when given (realtime and fast timing), is how much later than `at` the delivery went out by
/// the wall clock: written as "late_us".
std::string sent_record(const std::string& port, std::span<const std::uint8_t> bytes,
                        sim::SimTime at, wire::Protocol protocol,
                        std::optional<sim::SimDuration> late = std::nullopt);

}  // namespace dxlemu::app
