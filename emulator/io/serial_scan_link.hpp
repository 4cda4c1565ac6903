#pragma once

#include <string>

#include "scan/scan_link.hpp"
#include "wire/status_reader.hpp"

namespace dxlemu::io {

/// The scan link of `dxlemu clone` on a serial device (a U2D2, or a PTY): raw 8N1 at any rate
/// (TCSETS2/BOTHER), no flow control. Input that arrives between exchanges (a late reply, line
/// noise) is discarded before each send.
class SerialScanLink final : public scan::ScanLink {
 public:
  /// Opens `path`; throws std::system_error naming it when it cannot.
  explicit SerialScanLink(const std::string& path);
  ~SerialScanLink() override;
  SerialScanLink(const SerialScanLink&) = delete;
  SerialScanLink& operator=(const SerialScanLink&) = delete;

  void set_baud(std::uint32_t bps) override;
  std::vector<wire::StatusPacket> exchange(const wire::InstructionPacket& packet,
                                           std::size_t max_replies,
                                           std::chrono::microseconds timeout) override;

 private:
  std::string path_;
  int fd_ = -1;
};

}  // namespace dxlemu::io
