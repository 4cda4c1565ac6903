#pragma once

#include <cstdint>
#include <span>

namespace dxlemu::wire {

/// The CRC-16/MODBUS of `bytes` (address through the last data byte): polynomial 0xA001 (0x8005
/// reflected), initial value 0xFFFF, no final XOR (modbus-rtu.md "RTU framing"). A frame carries
/// it low byte first. Check value of "123456789": 0x4B37.
std::uint16_t crc16_modbus(std::span<const std::uint8_t> bytes);

}  // namespace dxlemu::wire
