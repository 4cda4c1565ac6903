#include "app/pcap_writer.hpp"

#include <algorithm>
#include <optional>

#include "wire/framer.hpp"

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

// A framer holds at most one partial packet (4 KiB in Protocol 2.0) when it reports a failure,
// so the bytes of any damaged packet are among the last few KiB the client wrote. Tapes are cut
// back to kTapeKeep bytes once they exceed twice that, which keeps the copying amortised.
constexpr std::size_t kTapeKeep = std::size_t{16} * 1024;

template <typename T>
void put_le(std::ostream& out, T value) {
  for (std::size_t i = 0; i < sizeof(T); ++i) {
    out.put(
        static_cast<char>((static_cast<std::uint64_t>(value) >> (kBitsPerByte * i)) & kByteMask));
  }
}

std::size_t protocol_index(wire::Protocol protocol) {
  return protocol == wire::Protocol::V1 ? 0 : 1;
}

// Where the damaged packet that `failure` reports starts in `tape`, searching from `from`: the
// first position holding the protocol's header (as much of it as the failure covers), then the
// failure's ID and instruction where it knows them, and for a bad check a LENGTH that makes the
// packet exactly failure.bytes long. Garbage never reaches the observer, so the search may have
// to skip some.
std::optional<std::size_t> find_failure(const std::vector<std::uint8_t>& tape, std::size_t from,
                                        const wire::FramingError& failure) {
  const wire::FrameFormat format = wire::FrameFormat::for_protocol(failure.protocol);
  const std::size_t header = format.header.size();
  const std::size_t id_at = header;
  const std::size_t length_at = id_at + 1;
  const std::size_t instruction_at = length_at + format.length_field_bytes;
  const std::size_t n = failure.bytes;
  if (n == 0 || tape.size() < n) {
    return std::nullopt;
  }
  for (std::size_t pos = from; pos + n <= tape.size(); ++pos) {
    const auto packet = std::span(tape).subspan(pos, n);
    const std::size_t compared = std::min(n, header);
    if (!std::equal(format.header.begin(),
                    format.header.begin() + static_cast<std::ptrdiff_t>(compared),
                    packet.begin())) {
      continue;
    }
    if (failure.id && (n <= id_at || packet[id_at] != *failure.id)) {
      continue;
    }
    if (failure.instruction && n > instruction_at &&
        packet[instruction_at] != *failure.instruction) {
      continue;
    }
    if (failure.kind == wire::FramingErrorKind::BadCheck) {
      if (n < instruction_at) {
        continue;
      }
      std::size_t length = 0;
      for (std::size_t i = 0; i < format.length_field_bytes; ++i) {
        length |= std::size_t{packet[length_at + i]} << (kBitsPerByte * i);
      }
      if (instruction_at + length != n) {
        continue;
      }
    }
    return pos;
  }
  return std::nullopt;
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

PcapWriter::Tape& PcapWriter::tape(std::size_t port) {
  if (port >= tapes_.size()) {
    tapes_.resize(port + 1);
  }
  return tapes_[port];
}

void PcapWriter::client_bytes(std::size_t port, std::span<const std::uint8_t> bytes) {
  Tape& t = tape(port);
  t.bytes.insert(t.bytes.end(), bytes.begin(), bytes.end());
  if (t.bytes.size() > 2 * kTapeKeep) {
    const std::size_t cut = t.bytes.size() - kTapeKeep;
    t.bytes.erase(t.bytes.begin(), t.bytes.begin() + static_cast<std::ptrdiff_t>(cut));
    for (std::size_t& next : t.next) {
      next = next > cut ? next - cut : 0;
    }
  }
}

void PcapWriter::heard(std::size_t port, const wire::FramerEvent& event) {
  Tape& t = tape(port);
  if (const auto* frame = std::get_if<wire::Frame>(&event)) {
    // Only to keep the search for damaged packets in step: the frame brings its own bytes.
    std::size_t& next = t.next[protocol_index(frame->protocol)];
    const auto begin = t.bytes.begin() + static_cast<std::ptrdiff_t>(next);
    const auto found = std::search(begin, t.bytes.end(), frame->raw.begin(), frame->raw.end());
    if (found != t.bytes.end()) {
      next = static_cast<std::size_t>(found - t.bytes.begin()) + frame->raw.size();
    }
    write(PcapDirection::ToServos, static_cast<std::uint8_t>(frame->protocol), port,
          frame->last_byte_at, frame->raw);
    return;
  }
  const auto& failure = std::get<wire::FramingError>(event);
  std::size_t& next = t.next[protocol_index(failure.protocol)];
  const auto pos = find_failure(t.bytes, next, failure);
  if (!pos) {
    return;
  }
  // The framer rescans from the byte after a failed header, so a later packet may start inside
  // this one's bytes.
  next = *pos + 1;
  write(PcapDirection::ToServos, static_cast<std::uint8_t>(failure.protocol), port, failure.at,
        std::span(t.bytes).subspan(*pos, failure.bytes));
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
