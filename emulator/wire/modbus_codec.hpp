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

/// A Modbus response as a master reads it (modbus-rtu.md "Exception responses" and the normal
/// response of each function).
struct ModbusResponse {
  std::uint8_t address = 0;
  /// The function it answers, without the exception bit (0x80).
  std::uint8_t function = 0;
  /// The exception code of an exception response (function | 0x80, code); 0: a normal response.
  std::uint8_t exception = 0;
  /// Read Holding/Input Registers, Read/Write Multiple Registers: the registers read, as the
  /// control-table bytes they hold (each register's low byte first). Write Single Register,
  /// Write Multiple Registers, Diagnostics: the data field as it came (the echo).
  std::vector<std::uint8_t> data;
  bool operator==(const ModbusResponse&) const = default;
};

/// Decodes a Modbus response frame (a master's: tests, `dxlemu clone`): an exception response
/// carries one byte, its code; a read's response a byte count then that many bytes, an even
/// number; the others are taken as they come. A frame that does not fit its function's layout,
/// or answers a function the DYNAMIXEL servers do not serve, is NotStatus.
DecodeResult<ModbusResponse> decode_modbus_response(const Frame& frame);

/// The control-table bytes the data of a read's normal response carries (a byte count, then
/// that many bytes of registers, each big-endian), each register's low byte first; nullopt when
/// the data is not that (decode_modbus_status() leaves a response's data as it came).
std::optional<std::vector<std::uint8_t>> registers_read(std::span<const std::uint8_t> data);

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
