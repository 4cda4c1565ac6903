#include "app/daemon/trace_fan_out.hpp"

#include <algorithm>
#include <fstream>

#include "app/config/bus_config.hpp"
#include "app/record/trace_record.hpp"

namespace dxlemu::app {

TraceFanOut::TraceFanOut(std::unique_ptr<std::ostream> trace, std::unique_ptr<std::ostream> pcap,
                         std::chrono::microseconds pcap_start)
    : trace_(std::move(trace)), pcap_file_(std::move(pcap)) {
  if (pcap_file_) {
    pcap_ = std::make_unique<PcapWriter>(*pcap_file_, pcap_start);
  }
}

TraceFanOut::~TraceFanOut() = default;

std::unique_ptr<TraceFanOut> TraceFanOut::open(const std::optional<std::filesystem::path>& trace,
                                               const std::optional<std::filesystem::path>& pcap,
                                               std::chrono::microseconds pcap_start) {
  std::unique_ptr<std::ofstream> trace_file;
  if (trace) {
    trace_file = std::make_unique<std::ofstream>(*trace, std::ios::trunc);
    if (!*trace_file) {
      throw ConfigError(trace->string(), "", "cannot be created (--trace)");
    }
  }
  std::unique_ptr<std::ofstream> pcap_file;
  if (pcap) {
    pcap_file = std::make_unique<std::ofstream>(*pcap, std::ios::binary | std::ios::trunc);
    if (!*pcap_file) {
      throw ConfigError(pcap->string(), "", "cannot be created (--pcap)");
    }
  }
  return std::make_unique<TraceFanOut>(std::move(trace_file), std::move(pcap_file), pcap_start);
}

bus::LineObserver TraceFanOut::observer(const std::string& port, std::size_t index,
                                        Clock wall_now) {
  return {[this, port, index](const wire::FramerEvent& event) {
            if (tracing()) {
              trace(port, heard_record(port, event));
            }
            if (pcap_) {
              pcap_->heard(index, event);
            }
          },
          [this, port, index, wall_now = std::move(wall_now)](std::span<const std::uint8_t> bytes,
                                                              sim::SimTime at, wire::Protocol p) {
            if (tracing()) {
              // As the late-reply guard measures it: never early.
              const auto late = wall_now
                                    ? std::optional(std::max(sim::SimDuration{0}, wall_now() - at))
                                    : std::nullopt;
              trace(port, sent_record(port, bytes, at, p, late));
            }
            if (pcap_) {
              pcap_->sent(index, bytes, at, p);
            }
          }};
}

void TraceFanOut::trace(const std::string& port, const std::string& line) {
  if (trace_) {
    *trace_ << line << '\n';  // flushed when the handler is done (flush())
  }
  if (subscribers_.empty()) {
    return;
  }
  // The same members after "event": a record is never empty, so `line` is "{...,...}".
  const std::string event = R"({"event":"trace",)" + line.substr(1);
  for (auto& [id, subscriber] : subscribers_) {
    if (subscriber.ports.empty() || std::find(subscriber.ports.begin(), subscriber.ports.end(),
                                              port) != subscriber.ports.end()) {
      subscriber.connection.send(event);
    }
  }
}

void TraceFanOut::subscribe(const control::Connection& connection, std::vector<std::string> ports) {
  subscribers_[connection.id] = {connection, std::move(ports)};
}

void TraceFanOut::unsubscribe(std::uint64_t id) {
  subscribers_.erase(id);
}

void TraceFanOut::flush() {
  if (trace_) {
    trace_->flush();
  }
}

}  // namespace dxlemu::app
