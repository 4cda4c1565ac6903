#include "app/record/pcap_writer.hpp"

#include <algorithm>

namespace dxlemu::app {
namespace {

// Classic pcap (https://wiki.wireshark.org/Development/LibpcapFileFormat): version 2.4 with
// microsecond timestamps; written little-endian on every host so that captures are identical.
constexpr std::uint32_t kPcapMagic = 0xa1b2c3d4;
constexpr std::uint16_t kPcapVersionMajor = 2;
constexpr std::uint16_t kPcapVersionMinor = 4;
constexpr std::int64_t kMicrosecondsPerSecond = 1'000'000;
constexpr std::int64_t kNanosecondsPerMicrosecond = 1'000;
constexpr unsigned kBitsPerByte = 8;
constexpr std::uint32_t kByteMask = 0xFF;

template <typename T>
void put_le(std::ostream& out, T value) {
  for (std::size_t i = 0; i < sizeof(T); ++i) {
    out.put(
        static_cast<char>((static_cast<std::uint64_t>(value) >> (kBitsPerByte * i)) & kByteMask));
  }
}

}  // namespace

PcapWriter::PcapWriter(std::ostream& out, std::chrono::microseconds start)
    : out_(out), start_(start) {
  put_le(out_, kPcapMagic);
  put_le(out_, kPcapVersionMajor);
  put_le(out_, kPcapVersionMinor);
  put_le(out_, std::int32_t{0});   // thiszone: timestamps are UTC
  put_le(out_, std::uint32_t{0});  // sigfigs: always 0
  put_le(out_, kPcapSnapLength);
  put_le(out_, kPcapLinkType);
  out_.flush();
}

void PcapWriter::heard(std::size_t port, const wire::FramerEvent& event) {
  if (const auto* frame = std::get_if<wire::Frame>(&event)) {
    write(PcapDirection::ToServos, static_cast<std::uint8_t>(frame->protocol), port,
          frame->last_byte_at, frame->raw);
    return;
  }
  const auto& failure = std::get<wire::FramingError>(event);
  if (failure.kind == wire::FramingErrorKind::Garbage) {
    return;
  }
  write(PcapDirection::ToServos, static_cast<std::uint8_t>(failure.protocol), port, failure.at,
        failure.raw);
}

void PcapWriter::sent(std::size_t port, std::span<const std::uint8_t> bytes, sim::SimTime at,
                      wire::Protocol protocol) {
  write(PcapDirection::ToClient, static_cast<std::uint8_t>(protocol), port, at, bytes);
}

void PcapWriter::write(PcapDirection direction, std::uint8_t protocol, std::size_t port,
                       sim::SimTime at, std::span<const std::uint8_t> bytes) {
  const std::int64_t us = start_.count() + sim::ns_since_start(at) / kNanosecondsPerMicrosecond;
  const std::size_t original = kPcapPseudoHeaderBytes + bytes.size();
  const std::size_t captured = std::min<std::size_t>(original, kPcapSnapLength);
  put_le(out_, static_cast<std::uint32_t>(us / kMicrosecondsPerSecond));
  put_le(out_, static_cast<std::uint32_t>(us % kMicrosecondsPerSecond));
  put_le(out_, static_cast<std::uint32_t>(captured));
  put_le(out_, static_cast<std::uint32_t>(original));
  out_.put(static_cast<char>(kPcapPseudoHeaderVersion));
  out_.put(static_cast<char>(direction));
  out_.put(static_cast<char>(protocol));
  out_.put(static_cast<char>(port < kPcapPortOverflow ? port : kPcapPortOverflow));
  out_.write(reinterpret_cast<const char*>(bytes.data()),
             static_cast<std::streamsize>(captured - kPcapPseudoHeaderBytes));
  out_.flush();
}

}  // namespace dxlemu::app
