#pragma once

#include <cstdint>
#include <span>
#include <vector>

namespace dxlemu::wire {

/// Protocol 2.0 byte stuffing (protocol2.md "Packet Process"): returns `region` with 0xFD inserted
/// after every FF FF FD, so that no header can appear inside a packet. The region is the part of a
/// packet between LEN_H and the CRC (instruction, error and parameters).
std::vector<std::uint8_t> stuff(std::span<const std::uint8_t> region);

/// Undoes stuff(): drops the 0xFD that follows each FF FF FD. A bare FF FF FD not followed by 0xFD
/// (a sender that did not stuff) is kept as it is, so unstuff never fails.
std::vector<std::uint8_t> unstuff(std::span<const std::uint8_t> region);

}  // namespace dxlemu::wire
