#pragma once

#include <cstdint>
#include <vector>

#include "wire/instruction.hpp"

namespace dxlemu::wire {

/// Builds the instruction packet a controller would send: the client side of the codec, used by
/// tests, benchmarks and tools. Throws std::invalid_argument for what the protocol cannot express
/// (a 2.0-only instruction in 1.0, a 1.0 address or length over 255, Sync Write data whose size
/// differs from its length): caller bugs, never a reaction to input.
std::vector<std::uint8_t> encode_instruction(const InstructionPacket& packet);

/// The instruction byte of a decoded instruction.
std::uint8_t instruction_code(const Instruction& instruction);

}  // namespace dxlemu::wire
