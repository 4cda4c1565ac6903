#pragma once

#include <cstddef>

/// The fixed sizes of the pcap file format (a 24-byte global header, a 16-byte header before each
/// record), as the format defines them: the tests check the writer's bytes against these, not
/// against the writer's own constants.
namespace dxlemu::test::pcap {

inline constexpr std::size_t kGlobalHeaderBytes = 24;
inline constexpr std::size_t kRecordHeaderBytes = 16;

}  // namespace dxlemu::test::pcap
