#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "app/record/pcap_writer.hpp"
#include "bus/bus.hpp"
#include "control/connection.hpp"

namespace dxlemu::app {

/// Where the packets crossing every port's line go: the trace file (--trace, JSON lines,
/// docs/trace.md), the capture (--pcap, docs/pcap.md) and the control API's trace subscribers
/// (trace.subscribe), all at once. Each port's bus gets one observer from it; a trace record is
/// built once per packet, and only when a trace file or a subscriber wants it. Apart from open(),
/// which creates the files, it only writes to the streams it owns and calls the subscribers' send.
class TraceFanOut {
 public:
  /// Writes trace lines to `trace` and a capture whose simulated time zero is the wall-clock time
  /// `pcap_start` (microseconds since the Unix epoch) to `pcap`; either may be null (none). The
  /// capture's global header is written at once.
  TraceFanOut(std::unique_ptr<std::ostream> trace, std::unique_ptr<std::ostream> pcap,
              std::chrono::microseconds pcap_start);

  /// The files of --trace and --pcap (either may be absent), created or truncated. Throws
  /// ConfigError naming the file and its option when one cannot be created.
  static std::unique_ptr<TraceFanOut> open(const std::optional<std::filesystem::path>& trace,
                                           const std::optional<std::filesystem::path>& pcap,
                                           std::chrono::microseconds pcap_start);

  TraceFanOut(const TraceFanOut&) = delete;
  TraceFanOut& operator=(const TraceFanOut&) = delete;
  ~TraceFanOut();

  /// The present by the wall clock, on simulated time's scale (what the late-reply guard reads).
  using Clock = std::function<sim::SimTime()>;

  /// The observer for the bus of the port named `port`, number `index` in config order (the
  /// capture's port byte). With `wall_now` (realtime and fast timing), each `out` record says how
  /// late its delivery went out against its modelled time ("late_us"). The fan-out must outlive
  /// the bus's use of it.
  bus::LineObserver observer(const std::string& port, std::size_t index, Clock wall_now = {});

  /// Sends the trace events of `ports` (every port when empty) to `connection` from now on,
  /// replacing an earlier subscription of that connection; keeps a copy of it until
  /// unsubscribe().
  void subscribe(const control::Connection& connection, std::vector<std::string> ports);
  /// Ends connection `id`'s trace events (unsubscribed, or closed); nothing when it has none.
  void unsubscribe(std::uint64_t id);

  /// Flushes the trace file: called once per I/O handler rather than per line, since a round
  /// trip writes two lines and a reader (tail -f) still sees each packet as soon as the daemon is
  /// done with it. The capture flushes each record itself.
  void flush();

 private:
  /// Whether anyone reads trace records: built only then.
  bool tracing() const { return trace_ != nullptr || !subscribers_.empty(); }
  /// Writes one trace record of `port` (a JSON object on one line) to the trace file and to the
  /// subscribers of that port.
  void trace(const std::string& port, const std::string& line);

  struct Subscriber {
    control::Connection connection;
    std::vector<std::string> ports;  // all when empty
  };
  std::unique_ptr<std::ostream> trace_;
  std::unique_ptr<std::ostream> pcap_file_;
  std::unique_ptr<PcapWriter> pcap_;                 // writes to pcap_file_; null without it
  std::map<std::uint64_t, Subscriber> subscribers_;  // by connection id
};

}  // namespace dxlemu::app
