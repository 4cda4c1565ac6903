#pragma once

#include <cstdint>
#include <vector>

#include "wire/instruction.hpp"

namespace dxlemu::wire {

/// Builds the instruction packet a controller would send: the client side of the codec, used by
/// tests, benchmarks and tools. Throws std::invalid_argument for what the protocol cannot express
/// (an instruction the protocol does not define, such as a 2.0-only one in 1.0 or a FEETECH-only
/// one in DYNAMIXEL; a 1.0 or FEETECH address or length over 255; Sync Write data whose size
/// differs from its length): caller bugs, never a reaction to input.
std::vector<std::uint8_t> encode_instruction(const InstructionPacket& packet);

/// The instruction byte of a decoded instruction.
std::uint8_t instruction_code(const Instruction& instruction);

/// The instruction byte that carries `instruction` in `protocol` (Modbus RTU: its function
/// code, modbus_function_of()).
std::uint8_t instruction_code(Protocol protocol, const Instruction& instruction);

}  // namespace dxlemu::wire
