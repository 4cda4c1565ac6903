#include "io/serial_scan_link.hpp"

#include <fcntl.h>
#include <poll.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <system_error>

#include "io/errno_error.hpp"
#include "io/raw_serial.hpp"
#include "wire/instruction_encoder.hpp"

namespace dxlemu::io {
namespace {

using Clock = std::chrono::steady_clock;

}  // namespace

SerialScanLink::SerialScanLink(const std::string& path)
    : path_(path), fd_(::open(path.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC)) {
  if (fd_ < 0) {
    throw_errno("cannot open " + path);
  }
}

SerialScanLink::~SerialScanLink() {
  ::close(fd_);
}

void SerialScanLink::set_baud(std::uint32_t bps) {
  set_raw_serial(fd_, bps, path_);
}

std::vector<wire::StatusPacket> SerialScanLink::exchange(const wire::InstructionPacket& packet,
                                                         std::size_t max_replies,
                                                         std::chrono::microseconds timeout) {
  discard_input(fd_);
  const std::vector<std::uint8_t> bytes = wire::encode_instruction(packet);
  std::size_t sent = 0;
  while (sent < bytes.size()) {
    const ssize_t n = ::write(fd_, bytes.data() + sent, bytes.size() - sent);
    if (n < 0 && errno != EINTR && errno != EAGAIN) {
      throw_errno(path_ + ": write");
    }
    sent += n > 0 ? static_cast<std::size_t>(n) : 0;
  }
  // The framer takes arrival times; time since the send stands in for the simulated time.
  const Clock::time_point start = Clock::now();
  // A frame that ends at a silence (Modbus RTU) cannot be timed here: a USB adapter hands the
  // bytes over in chunks, with gaps longer than the silence. Every chunk is fed at one instant,
  // and a reply is taken as ended once the bytes so far make a whole response (a good CRC and
  // the layout of its function), or when no more bytes come.
  const bool silence_delimited =
      wire::traits(packet.protocol).frame.delimiting == wire::Delimiting::Silence;
  wire::StatusReader reader(packet.protocol);
  std::vector<wire::StatusPacket> replies;
  std::array<std::uint8_t, 512> buffer{};
  Clock::time_point give_up = start + timeout;
  while (replies.size() < max_replies) {
    const auto left = std::chrono::ceil<std::chrono::milliseconds>(give_up - Clock::now());
    pollfd p{fd_, POLLIN, 0};
    if (left.count() <= 0 || poll(&p, 1, static_cast<int>(left.count())) <= 0) {
      break;
    }
    const ssize_t n = ::read(fd_, buffer.data(), buffer.size());
    if (n < 0 && errno != EINTR && errno != EAGAIN) {
      throw_errno(path_ + ": read");
    }
    if (n <= 0) {
      continue;
    }
    const Clock::time_point now = Clock::now();
    const auto chunk = std::span(buffer).first(static_cast<std::size_t>(n));
    if (silence_delimited) {
      reader.feed(chunk, sim::SimTime{}, replies);
      wire::StatusReader ended = reader;
      std::vector<wire::StatusPacket> whole;
      ended.end_of_write(whole);
      if (!whole.empty()) {
        reader = std::move(ended);
        replies.insert(replies.end(), whole.begin(), whole.end());
      }
    } else {
      reader.feed(chunk, sim::SimTime{std::chrono::duration_cast<sim::SimDuration>(now - start)},
                  replies);
    }
    give_up = now + timeout;
  }
  if (silence_delimited && replies.size() < max_replies) {
    reader.end_of_write(replies);
  }
  return replies;
}

}  // namespace dxlemu::io
