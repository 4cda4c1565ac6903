#pragma once

// Modbus RTU requests and responses (modbus-rtu.md) on the control table: holding register
// 40001 + floor(A / 2) holds control-table bytes A (low byte) and A + 1 (high byte) of an even
// address A, so a register read is a Read of twice as many bytes from twice its address, and a
// register write a Write. Values are big-endian on the wire; the table is little-endian.

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "wire/frame.hpp"
#include "wire/instruction.hpp"
#include "wire/instruction_decoder.hpp"
#include "wire/status.hpp"

namespace dxlemu::wire {

/// Decodes a Modbus request in the spec's order of checks: a function code it does not serve
/// (or a Diagnostics sub-function other than Return Query Data) is UnknownInstruction; a
/// quantity or byte count out of its range is BadValue, a data field of the wrong size
/// BadLength, registers beyond 16-bit byte addresses BadAddress.
DecodeResult<InstructionPacket> decode_modbus_request(const Frame& frame);

/// A Modbus response as a status: the exception code as its error (0 for a normal response)
/// and the response's data after the function code as its parameters (for traces; a master
/// that needs the registers reads them from the data).
StatusPacket decode_modbus_status(const Frame& frame);

/// Builds a Modbus response frame from `address`, answering function `function`: an exception
/// response when `exception` is not 0, else the normal response, which reads `request` (the
/// echo of Write Single Register, the start and quantity of Write Multiple Registers) and
/// carries `table_bytes` (what a register read read, in control-table order) as registers.
std::vector<std::uint8_t> encode_modbus_response(std::uint8_t address, std::uint8_t function,
                                                 const Instruction* request, std::uint8_t exception,
                                                 std::span<const std::uint8_t> table_bytes);

/// The function code that carries `instruction` in Modbus RTU: Read 03 (Read Holding
/// Registers), a one-register Write 06, a longer one 16, WriteRead 23, Echo 08, an
/// UnknownInstruction its own byte; nullopt for an instruction Modbus has no function for.
std::optional<std::uint8_t> modbus_function_of(const Instruction& instruction);

/// Builds the Modbus request frame of `packet` (a master's: tests, `dxlemu clone`), with the
/// function modbus_function_of() gives. Throws std::invalid_argument for an instruction Modbus
/// cannot carry, or a Read or Write not of whole registers.
std::vector<std::uint8_t> encode_modbus_request(const InstructionPacket& packet);

/// Builds a Modbus frame: address, function, data, CRC.
std::vector<std::uint8_t> encode_modbus_frame(std::uint8_t address, std::uint8_t function,
                                              std::span<const std::uint8_t> data);

}  // namespace dxlemu::wire
