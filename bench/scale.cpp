// Scale: dxlemu with many servos on one bus, and many ports in one process.
//
// 1. One bus of 253 XM430-W350 (IDs 0 ~ 252) at 1 Mbit/s, realtime timing. N times each (one at
//    a time, as a controller does): a Sync Read of Present Position (4 B) listing all 253 IDs,
//    in a shuffled order so that "list order" and "ID order" differ, and a broadcast Ping. Every
//    reply is checked with the codec: framed, decoded, from the expected ID at its place in the
//    chain (Sync Read: list order; broadcast Ping: ascending ID), error 0, the expected number of
//    parameters. The time of every reply is measured against its modelled time:
//
//      modelled end of reply k = wire(instruction)
//                              + Σ over replies j <= k: processing + Return Delay Time + wire(j)
//      lateness of reply k     = (steady_clock when the read() that completed reply k returned)
//                              - (steady_clock when the write() of the instruction returned
//                                 + modelled end of reply k)
//
//    (the chain of docs/bus.md, as reply_latency measures it for 10 servos). Reported: lateness of
//    the last reply (min, median, max over the N chains) and the earliest and latest of any reply;
//    a chain whose write() took over 100 µs is checked but not timed ("skipped"). Then dxlemu's
//    startup time, peak RSS (VmHWM) and CPU time, and the RSS a servo adds, from a first dxlemu
//    with one servo.
// 2. 32 ports in one process: a config file (docs/config.md) of ports p0 ~ p31, each with six
//    XM430-W350 (IDs 1 ~ 6) at 1 Mbit/s and its own link in a temporary directory. The bench
//    checks that every servo of every port answers a Ping, then measures dxlemu
//    (a) serving: one poll loop keeps a Read 4 B round trip going on every port, for D seconds
//        (IDs 1 ~ 6 in turn); round trips per second, their lateness (as above, one reply),
//        dxlemu's CPU use; then the same on p0 alone, to show what the other 31 ports add;
//    (b) idle: D seconds with every port open and no traffic, then D seconds with every port
//        closed; dxlemu's CPU use and context switches (the target is ≈ 0: nothing is due);
//    (c) peak RSS after start and after serving, and per servo;
//    (d) the time from starting dxlemu to its last readiness line.
//
// CPU use is the daemon's run time (/proc/PID/task/*/schedstat, ns) over wall time, in % of one
// CPU, with the same from the clock ticks of /proc/PID/stat (10 ms each) beside it; context
// switches are voluntary + involuntary from /proc/PID/status.
// Markdown tables go to stdout, progress to stderr.
//
// Usage: scale --dxlemu PATH [--seconds D] [--count N] [--cpu N]
// --cpu N pins the bench, and the dxlemu it starts, to CPU N (as reply_latency does).
#include <poll.h>
#include <stdlib.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <span>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "bus/line_timing.hpp"
#include "support/bench_main.hpp"
#include "support/daemon.hpp"
#include "support/flags.hpp"
#include "support/serial_port.hpp"
#include "support/stats.hpp"
#include "support/temp_dir.hpp"
#include "support/xm430.hpp"
#include "wire/framer.hpp"
#include "wire/instruction_decoder.hpp"
#include "wire/instruction_encoder.hpp"
#include "wire/packet_encoder.hpp"

namespace {

using dxlemu::bench::Clock;
using std::chrono::microseconds;
using std::chrono::milliseconds;
using std::chrono::nanoseconds;
namespace bench = dxlemu::bench;
using dxlemu::bench::fixed;
namespace wire = dxlemu::wire;

constexpr const char* kModel = "xm430-w350";
constexpr std::uint32_t kBaud = 1'000'000;
// Every ID a 2.0 servo may have: 0 ~ 252 (253 ~ 255 are reserved and broadcast).
constexpr int kBusServos = 253;
// The Sync Read lists ID (k × kShuffleStep) mod 253 at place k: 97 and 253 (11 × 23) have no
// common factor, so every ID comes once, and neighbours in the list are far apart in ID.
constexpr int kShuffleStep = 97;
constexpr std::size_t kPorts = 32;
constexpr std::uint8_t kServosPerPort = 6;

using dxlemu::bench::kMaxWriteTime;
using dxlemu::bench::kPingParams;
using dxlemu::bench::kPresentPosition;
using dxlemu::bench::kProcessing;
using dxlemu::bench::kReplyTimeout;
using dxlemu::bench::kReturnDelay;
constexpr std::uint16_t kItemSize = dxlemu::bench::kPresentPositionSize;
// After each chain, how long to listen for bytes nobody asked for (duplicates, stray replies).
constexpr milliseconds kStrayWindow{5};
// After the serving phase, how long the replies still in flight get before they are discarded.
constexpr milliseconds kDrain{100};

constexpr double kMedian = 0.5;

/// The name, and the link's file name, of port `index` of the many-ports config: p0, p1, ...
std::string port_name(std::size_t index) {
  std::string name = "p";
  name += std::to_string(index);
  return name;
}
constexpr double kP99 = 0.99;
constexpr double kPercent = 100.0;
constexpr double kKibPerMib = 1024.0;

struct Options {
  std::string dxlemu;
  double seconds = 5;
  int count = 20;
  int cpu = -1;
};

std::string ms(nanoseconds d) {
  return fixed(std::chrono::duration<double, std::milli>(d).count(), 1);
}

// A 2.0 status packet's size with `params` parameter bytes.
std::size_t status_size(std::size_t params) {
  return wire::encode_status({wire::Protocol::V2, 1, 0, std::vector<std::uint8_t>(params)}).size();
}

// What a process used over an interval: run time to the ns, clock ticks, context switches.
struct Usage {
  Clock::time_point wall;
  nanoseconds run{};
  nanoseconds ticks{};
  long voluntary = 0;
  long involuntary = 0;
};

Usage usage(pid_t pid) {
  return {Clock::now(), bench::run_time(pid), bench::cpu_time(pid),
          bench::proc_status_number(pid, "voluntary_ctxt_switches"),
          bench::proc_status_number(pid, "nonvoluntary_ctxt_switches")};
}

struct Interval {
  Usage from;
  Usage to;
  double seconds() const { return std::chrono::duration<double>(to.wall - from.wall).count(); }
  // CPU use in % of one CPU.
  double cpu_percent(bool ticks = false) const {
    const nanoseconds used = ticks ? to.ticks - from.ticks : to.run - from.run;
    return kPercent * std::chrono::duration<double>(used).count() / seconds();
  }
  long switches() const {
    return (to.voluntary - from.voluntary) + (to.involuntary - from.involuntary);
  }
  std::string describe() const {
    return fixed(cpu_percent(), 2) + " % (" + fixed(cpu_percent(true), 1) + " % by clock ticks), " +
           std::to_string(switches()) + " context switches (" +
           fixed(static_cast<double>(switches()) / seconds(), 1) + "/s)";
  }
};

// ---------------------------------------------------------------------------------------------
// 1. One bus of 253 servos

// A chain: one instruction, and the replies in the order they must come.
struct Chain {
  std::string name;
  std::vector<std::uint8_t> instruction;
  std::vector<std::uint8_t> ids;  // who answers, in order
  std::size_t params = 0;         // parameter bytes of every status

  std::size_t reply_size() const { return status_size(params); }
  std::size_t total_bytes() const { return ids.size() * reply_size(); }
  // Modelled end of reply k (0-based) after the instruction's write().
  nanoseconds modelled_end(std::size_t k) const {
    return dxlemu::bus::wire_time(instruction.size(), kBaud) +
           static_cast<long>(k + 1) *
               (kProcessing + kReturnDelay + dxlemu::bus::wire_time(reply_size(), kBaud));
  }
};

std::vector<Chain> chains() {
  std::vector<std::uint8_t> shuffled;
  std::vector<std::uint8_t> ascending;
  for (int k = 0; k < kBusServos; ++k) {
    shuffled.push_back(static_cast<std::uint8_t>(k * kShuffleStep % kBusServos));
    ascending.push_back(static_cast<std::uint8_t>(k));
  }
  return {
      {"Sync Read 4 B × 253 (shuffled list)",
       wire::encode_instruction({wire::Protocol::V2, wire::kBroadcastId,
                                 wire::SyncRead{kPresentPosition, kItemSize, shuffled}}),
       shuffled, kItemSize},
      {"broadcast Ping × 253",
       wire::encode_instruction({wire::Protocol::V2, wire::kBroadcastId, wire::Ping{}}), ascending,
       kPingParams},
  };
}

const char* kind_name(wire::FramingErrorKind kind) {
  switch (kind) {
    case wire::FramingErrorKind::Garbage:
      return "garbage";
    case wire::FramingErrorKind::BadCheck:
      return "bad CRC";
    case wire::FramingErrorKind::ImpossibleLength:
      return "impossible length";
    case wire::FramingErrorKind::Truncated:
      return "truncated";
  }
  return "?";
}

// What one chain looked like: how many replies were right, and the first thing that was wrong.
struct ChainCheck {
  std::size_t correct = 0;
  std::string problem;  // empty when every reply was right

  void note(const std::string& what) {
    if (problem.empty()) {
      problem = what;
    }
  }
};

// A reply is correct when it is framed, decodes as a status, comes from the ID expected at its
// place in the chain, has error 0 and the expected parameter count. A missing reply shifts the
// rest of the chain, which then counts as wrong: the order is part of the answer.
ChainCheck check_chain(std::span<const std::uint8_t> bytes, const Chain& chain) {
  wire::Framer framer(wire::Protocol::V2);
  std::vector<wire::FramerEvent> events;
  framer.feed(bytes, dxlemu::sim::SimTime{}, events);
  ChainCheck result;
  std::size_t place = 0;
  for (const wire::FramerEvent& event : events) {
    if (const auto* error = std::get_if<wire::FramingError>(&event)) {
      result.note(std::string("framing error (") + kind_name(error->kind) + ", " +
                  std::to_string(error->bytes) + " bytes) after reply " + std::to_string(place));
      continue;
    }
    const auto& frame = std::get<wire::Frame>(event);
    const std::size_t k = place++;
    const std::string where = "reply " + std::to_string(k + 1);
    if (k >= chain.ids.size()) {
      result.note("an extra reply from ID " + std::to_string(frame.id));
      continue;
    }
    const auto decoded = wire::decode_status(frame);
    const auto* status = std::get_if<wire::StatusPacket>(&decoded);
    if (status == nullptr) {
      result.note(where + " does not decode: " + std::get<wire::DecodeError>(decoded).reason);
    } else if (status->id != chain.ids[k]) {
      result.note(where + " is from ID " + std::to_string(status->id) + ", expected ID " +
                  std::to_string(chain.ids[k]));
    } else if (status->error != 0) {
      result.note(where + " (ID " + std::to_string(status->id) + ") has error " +
                  std::to_string(status->error));
    } else if (status->params.size() != chain.params) {
      result.note(where + " (ID " + std::to_string(status->id) + ") has " +
                  std::to_string(status->params.size()) + " parameter bytes");
    } else {
      ++result.correct;
    }
  }
  if (place < chain.ids.size()) {
    result.note("only " + std::to_string(place) + " of " + std::to_string(chain.ids.size()) +
                " replies arrived; the next expected was from ID " +
                std::to_string(chain.ids[place]) +
                (framer.buffered() > 0
                     ? ", " + std::to_string(framer.buffered()) + " bytes of a packet cut short"
                     : ""));
  }
  return result;
}

struct ChainResult {
  int complete = 0;                          // chains in which every reply was right
  int skipped = 0;                           // complete, but write() took over kMaxWriteTime
  std::size_t correct = 0;                   // right replies over all chains
  std::vector<nanoseconds> last;             // lateness of the last reply, per complete chain
  nanoseconds worst{nanoseconds::min()};     // the latest any reply of a complete chain was
  nanoseconds earliest{nanoseconds::max()};  // the earliest (negative: before its modelled time)
  std::string problem;                       // the first problem seen, with its repetition
};

// Bytes that arrive after a chain, within kStrayWindow: there should be none.
std::size_t strays(int fd) {
  std::array<std::uint8_t, 256> junk{};
  std::size_t n = 0;
  for (;;) {
    const auto arrivals = bench::read_arrivals(fd, junk, Clock::now() + kStrayWindow);
    if (arrivals.empty()) {
      return n;
    }
    n += arrivals.back().total;
  }
}

ChainResult measure_chain(int fd, const Chain& chain, int count) {
  ChainResult r;
  std::vector<std::uint8_t> buffer(chain.total_bytes());
  for (int rep = 1; rep <= count; ++rep) {
    bench::flush_input(fd);
    const Clock::time_point before = Clock::now();
    if (::write(fd, chain.instruction.data(), chain.instruction.size()) !=
        static_cast<ssize_t>(chain.instruction.size())) {
      bench::fail("write");
    }
    const Clock::time_point sent = Clock::now();
    const auto arrivals = bench::read_arrivals(
        fd, buffer, sent + chain.modelled_end(chain.ids.size() - 1) + kReplyTimeout);
    const std::size_t got = arrivals.empty() ? 0 : arrivals.back().total;
    ChainCheck check = check_chain(std::span(buffer).first(got), chain);
    if (const std::size_t extra = strays(fd); extra > 0) {
      check.note(std::to_string(extra) + " bytes after the last reply");
    }
    r.correct += check.correct;
    if (!check.problem.empty()) {
      const std::string problem = "repetition " + std::to_string(rep) + ": " + check.problem;
      std::cerr << "scale: " << chain.name << ": " << problem << "\n";
      if (r.problem.empty()) {
        r.problem = problem;
      }
      continue;
    }
    ++r.complete;
    if (sent - before > kMaxWriteTime) {
      ++r.skipped;
      continue;
    }
    // Reply k is complete with the first read() that brought its last byte.
    auto arrival = arrivals.begin();
    for (std::size_t k = 0; k < chain.ids.size(); ++k) {
      while (arrival->total < (k + 1) * chain.reply_size()) {
        ++arrival;
      }
      const nanoseconds lateness = arrival->at - (sent + chain.modelled_end(k));
      r.worst = std::max(r.worst, lateness);
      r.earliest = std::min(r.earliest, lateness);
    }
    r.last.push_back(arrivals.back().at - (sent + chain.modelled_end(chain.ids.size() - 1)));
  }
  return r;
}

// The peak RSS of a dxlemu with one servo, just started: what the process costs before servos
// and ports are added.
long baseline_kib(const Options& options, const bench::TempDir& dir) {
  std::cerr << "scale: dxlemu with 1 servo (baseline memory)\n";
  const bench::Daemon one(options.dxlemu,
                          {"--servo", std::string(kModel) + ":1", "--baud", std::to_string(kBaud),
                           "--link", (dir.path() / "one").string()});
  return bench::peak_rss_kib(one.pid());
}

void one_bus(const Options& options, const bench::TempDir& dir, long base_kib) {
  using bench::us;
  const std::string link = (dir.path() / "bus").string();
  const std::string servos = std::string(kModel) + ":0-" + std::to_string(kBusServos - 1);

  std::cerr << "scale: dxlemu with " << kBusServos << " servos on one bus\n";
  const Clock::time_point start = Clock::now();
  bench::Daemon daemon(options.dxlemu,
                       {"--servo", servos, "--baud", std::to_string(kBaud), "--link", link});
  const nanoseconds startup = Clock::now() - start;
  const long started_kib = bench::peak_rss_kib(daemon.pid());
  const nanoseconds startup_cpu = bench::run_time(daemon.pid());
  const int fd = bench::open_port(daemon.pty(), kBaud);

  std::cout << "### One bus of " << kBusServos << " servos (" << kModel << ", IDs 0 ~ "
            << kBusServos - 1 << ", " << kBaud << " bit/s, realtime)\n\n"
            << "| instruction | chains | complete | skipped | replies correct | modelled (ms) | "
               "last reply min (µs) | median (µs) | max (µs) | any reply: earliest (µs) | "
               "latest (µs) | first problem |\n"
               "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|"
            << std::endl;
  const Usage before = usage(daemon.pid());
  for (const Chain& chain : chains()) {
    std::cerr << "scale: " << chain.name << ", " << options.count << " times\n";
    ChainResult r = measure_chain(fd, chain, options.count);
    std::sort(r.last.begin(), r.last.end());
    std::cout << "| " << chain.name << " | " << options.count << " | " << r.complete << " | "
              << r.skipped << " | " << r.correct << " of "
              << chain.ids.size() * static_cast<std::size_t>(options.count) << " | "
              << ms(chain.modelled_end(chain.ids.size() - 1)) << " | ";
    if (r.last.empty()) {
      std::cout << "- | - | - | - | - | ";
    } else {
      std::cout << us(r.last.front()) << " | " << us(bench::percentile(r.last, kMedian)) << " | "
                << us(r.last.back()) << " | " << us(r.earliest) << " | " << us(r.worst) << " | ";
    }
    std::cout << (r.problem.empty() ? "-" : r.problem) << " |" << std::endl;
  }
  const Interval serving{before, usage(daemon.pid())};
  ::close(fd);
  const long peak_kib = bench::peak_rss_kib(daemon.pid());

  std::cout << "\n| dxlemu with " << kBusServos << " servos | value |\n|---|---|\n"
            << "| startup (to the readiness line) | " << ms(startup) << " ms, " << ms(startup_cpu)
            << " ms CPU |\n"
            << "| peak RSS after start / after the chains | " << started_kib << " / " << peak_kib
            << " KiB |\n"
            << "| peak RSS with 1 servo | " << base_kib << " KiB |\n"
            << "| RSS per servo ((" << kBusServos << " servos − 1 servo) / " << kBusServos - 1
            << ") | " << fixed(static_cast<double>(started_kib - base_kib) / (kBusServos - 1), 1)
            << " KiB |\n"
            << "| CPU while answering the chains | " << serving.describe() << " over "
            << fixed(serving.seconds(), 1) << " s |\n"
            << std::endl;
}

// ---------------------------------------------------------------------------------------------
// 2. 32 ports in one process

std::filesystem::path write_config(const bench::TempDir& dir) {
  nlohmann::json ports = nlohmann::json::array();
  std::vector<int> ids;
  for (int id = 1; id <= kServosPerPort; ++id) {
    ids.push_back(id);
  }
  for (std::size_t p = 0; p < kPorts; ++p) {
    const std::string name = port_name(p);
    ports.push_back({{"name", name},
                     {"link", (dir.path() / name).string()},
                     {"servos", {{{"model", kModel}, {"ids", ids}, {"baud", kBaud}}}}});
  }
  std::filesystem::path file = dir.path() / "ports.json";
  std::ofstream out(file);
  out << nlohmann::json{{"description", "scale bench: 32 ports of 6 servos"}, {"ports", ports}}
             .dump(2);
  if (!out) {
    throw std::runtime_error("cannot write " + file.string());
  }
  return file;
}

// True when `bytes` are one status from `id`, error 0, with `params` parameter bytes.
bool valid_status(std::span<const std::uint8_t> bytes, std::uint8_t id, std::size_t params) {
  wire::Framer framer(wire::Protocol::V2);
  std::vector<wire::FramerEvent> events;
  framer.feed(bytes, dxlemu::sim::SimTime{}, events);
  if (events.size() != 1 || !std::holds_alternative<wire::Frame>(events[0])) {
    return false;
  }
  const auto decoded = wire::decode_status(std::get<wire::Frame>(events[0]));
  const auto* status = std::get_if<wire::StatusPacket>(&decoded);
  return status != nullptr && status->id == id && status->error == 0 &&
         status->params.size() == params;
}

// Pings every servo of every port; returns the names of the ports where one did not answer.
std::vector<std::string> ping_all(const std::vector<int>& fds) {
  std::vector<std::string> failed;
  const std::size_t size = status_size(kPingParams);
  std::vector<std::uint8_t> reply(size);
  for (std::size_t p = 0; p < fds.size(); ++p) {
    bool ok = true;
    for (std::uint8_t id = 1; id <= kServosPerPort; ++id) {
      const auto ping = wire::encode_instruction({wire::Protocol::V2, id, wire::Ping{}});
      if (::write(fds[p], ping.data(), ping.size()) != static_cast<ssize_t>(ping.size())) {
        bench::fail("write");
      }
      const auto got = bench::read_exactly(fds[p], reply, Clock::now() + kReplyTimeout);
      if (!got || !valid_status(reply, id, kPingParams)) {
        std::cerr << "scale: p" << p << ": no valid answer to a Ping of ID " << int{id} << "\n";
        ok = false;
        bench::flush_input(fds[p]);
      }
    }
    if (!ok) {
      failed.push_back(port_name(p));
    }
  }
  return failed;
}

// One port's round trip in flight.
struct Client {
  int fd = -1;
  std::uint8_t id = 1;
  Clock::time_point sent;
  std::size_t got = 0;
  std::array<std::uint8_t, 32> reply{};
  std::vector<std::vector<std::uint8_t>> reference;  // per ID - 1: the first valid reply
};

struct Serving {
  long round_trips = 0;
  long lost = 0;  // no reply within the timeout, or not the expected one
  std::vector<nanoseconds> lateness;
  Interval daemon;
  Interval client;
};

// Keeps one Read 4 B round trip going on every port until `seconds` have passed, from one poll
// loop (one thread, as a controller with many adapters might; 32 threads would take the CPUs
// from dxlemu on a small machine).
Serving serve(std::span<Client> clients, pid_t daemon, double seconds) {
  std::vector<std::vector<std::uint8_t>> reads;
  for (std::uint8_t id = 1; id <= kServosPerPort; ++id) {
    reads.push_back(wire::encode_instruction(
        {wire::Protocol::V2, id, wire::Read{kPresentPosition, kItemSize}}));
  }
  const std::size_t size = status_size(kItemSize);
  const nanoseconds modelled = dxlemu::bus::wire_time(reads.front().size(), kBaud) + kProcessing +
                               kReturnDelay + dxlemu::bus::wire_time(size, kBaud);
  auto send = [&](Client& c) {
    c.got = 0;
    const auto& read = reads[c.id - 1];
    if (::write(c.fd, read.data(), read.size()) != static_cast<ssize_t>(read.size())) {
      bench::fail("write");
    }
    c.sent = Clock::now();
  };

  Serving s;
  std::vector<pollfd> fds;
  for (Client& c : clients) {
    c.reference.assign(kServosPerPort, {});
    fds.push_back({c.fd, POLLIN, 0});
  }
  const Usage daemon_before = usage(daemon);
  const Usage client_before = usage(getpid());
  const Clock::time_point end = Clock::now() + std::chrono::duration_cast<nanoseconds>(
                                                   std::chrono::duration<double>(seconds));
  for (Client& c : clients) {
    send(c);
  }
  for (Clock::time_point now = Clock::now(); now < end; now = Clock::now()) {
    Clock::time_point wake = end;
    for (const Client& c : clients) {
      wake = std::min(wake, c.sent + modelled + kReplyTimeout);
    }
    const auto wait = std::chrono::ceil<milliseconds>(wake - now);
    if (poll(fds.data(), fds.size(), static_cast<int>(std::max<long>(0, wait.count()))) < 0 &&
        errno != EINTR) {
      bench::fail("poll");
    }
    now = Clock::now();
    for (std::size_t p = 0; p < clients.size(); ++p) {
      Client& c = clients[p];
      if ((fds[p].revents & POLLIN) != 0) {
        const ssize_t n = ::read(c.fd, c.reply.data() + c.got, size - c.got);
        c.got += n > 0 ? static_cast<std::size_t>(n) : 0;
      }
      if (c.got == size) {
        const std::span<const std::uint8_t> bytes(c.reply.data(), size);
        std::vector<std::uint8_t>& reference = c.reference[c.id - 1];
        // The servos stand still: every later answer of one servo equals its first, checked one.
        const bool valid = reference.empty()
                               ? valid_status(bytes, c.id, kItemSize)
                               : std::equal(bytes.begin(), bytes.end(), reference.begin());
        if (valid && reference.empty()) {
          reference.assign(bytes.begin(), bytes.end());
        }
        ++s.round_trips;
        if (valid) {
          s.lateness.push_back(now - (c.sent + modelled));
        } else {
          ++s.lost;
          bench::flush_input(c.fd);
        }
        c.id = static_cast<std::uint8_t>(c.id % kServosPerPort + 1);
        send(c);
      } else if (now > c.sent + modelled + kReplyTimeout) {
        ++s.round_trips;
        ++s.lost;
        bench::flush_input(c.fd);
        send(c);
      }
    }
  }
  s.daemon = {daemon_before, usage(daemon)};
  s.client = {client_before, usage(getpid())};
  std::this_thread::sleep_for(kDrain);
  for (const Client& c : clients) {
    bench::flush_input(c.fd);
  }
  return s;
}

// The table rows of one serving phase, labelled `label`.
std::string serving_rows(const std::string& label, Serving s, std::size_t ports) {
  using bench::us;
  std::sort(s.lateness.begin(), s.lateness.end());
  const double rate = static_cast<double>(s.round_trips) / s.daemon.seconds();
  std::string rows = "| " + label + ": Read 4 B round trips | " + std::to_string(s.round_trips) +
                     " in " + fixed(s.daemon.seconds(), 1) + " s: " + fixed(rate, 0) + "/s (" +
                     fixed(rate / static_cast<double>(ports), 0) + "/s per port), " +
                     std::to_string(s.lost) + " lost |\n";
  if (!s.lateness.empty()) {
    rows += "| " + label + ": lateness median / p99 / max | " +
            us(bench::percentile(s.lateness, kMedian)) + " / " +
            us(bench::percentile(s.lateness, kP99)) + " / " + us(s.lateness.back()) + " µs |\n";
  }
  rows += "| " + label + ": dxlemu CPU | " + s.daemon.describe() + " |\n";
  rows += "| " + label + ": the bench's own CPU | " + fixed(s.client.cpu_percent(), 1) + " % |\n";
  return rows;
}

Interval idle(pid_t daemon, double seconds) {
  const Usage before = usage(daemon);
  std::this_thread::sleep_for(std::chrono::duration<double>(seconds));
  return {before, usage(daemon)};
}

void many_ports(const Options& options, const bench::TempDir& dir, long base_kib) {
  const std::filesystem::path config = write_config(dir);
  std::cerr << "scale: dxlemu with " << kPorts << " ports of " << int{kServosPerPort}
            << " servos\n";
  const Clock::time_point start = Clock::now();
  bench::Daemon daemon(options.dxlemu, {"--config", config.string()}, kPorts);
  const nanoseconds startup = Clock::now() - start;
  const long started_kib = bench::peak_rss_kib(daemon.pid());

  std::vector<Client> clients(kPorts);
  std::vector<int> fds;
  for (std::size_t p = 0; p < kPorts; ++p) {
    clients[p].fd = bench::open_port((dir.path() / port_name(p)).string(), kBaud);
    fds.push_back(clients[p].fd);
  }
  std::cerr << "scale: pinging every servo of every port\n";
  const std::vector<std::string> silent = ping_all(fds);

  std::cerr << "scale: Read 4 B round trips on " << kPorts << " ports for " << options.seconds
            << " s\n";
  const Serving all = serve(clients, daemon.pid(), options.seconds);
  const long served_kib = bench::peak_rss_kib(daemon.pid());
  // The same on one port: what the other 31 add to a round trip's lateness and cost.
  std::cerr << "scale: Read 4 B round trips on p0 alone for " << options.seconds << " s\n";
  const Serving alone = serve(std::span(clients).first(1), daemon.pid(), options.seconds);

  std::cerr << "scale: idle, ports open, " << options.seconds << " s\n";
  const Interval idle_open = idle(daemon.pid(), options.seconds);
  for (const int fd : fds) {
    ::close(fd);
  }
  std::cerr << "scale: idle, ports closed, " << options.seconds << " s\n";
  const Interval idle_closed = idle(daemon.pid(), options.seconds);

  const std::size_t servos = kPorts * kServosPerPort;
  std::string silent_list;
  for (const std::string& name : silent) {
    silent_list += " " + name;
  }
  std::cout << "### " << kPorts << " ports in one process (" << int{kServosPerPort} << " " << kModel
            << " each, " << kBaud << " bit/s, realtime)\n\n"
            << "| figure | value |\n|---|---|\n"
            << "| startup (to the last of " << kPorts << " readiness lines) | " << ms(startup)
            << " ms |\n"
            << "| ports where every servo answered a Ping | " << kPorts - silent.size() << " of "
            << kPorts << (silent.empty() ? "" : " (silent:" + silent_list + ")") << " |\n"
            << serving_rows("serving " + std::to_string(kPorts) + " ports", all, kPorts)
            << serving_rows("serving p0 alone", alone, 1) << "| idle, ports open: dxlemu CPU | "
            << idle_open.describe() << " |\n"
            << "| idle, ports closed: dxlemu CPU | " << idle_closed.describe() << " |\n"
            << "| peak RSS after start / after serving | " << started_kib << " / " << served_kib
            << " KiB (" << fixed(static_cast<double>(served_kib) / kKibPerMib, 1) << " MiB) |\n"
            << "| RSS per servo, ports included ((after serving − 1 servo) / " << servos << ") | "
            << fixed(static_cast<double>(served_kib - base_kib) / static_cast<double>(servos), 1)
            << " KiB |\n"
            << std::endl;
}

constexpr const char* kUsage = "usage: scale --dxlemu PATH [--seconds D] [--count N] [--cpu N]";

Options parse(int argc, char** argv) {
  Options o;
  dxlemu::bench::parse_flags(
      argc, argv,
      {{"--dxlemu", [&](const std::string& v) { o.dxlemu = v; }},
       {"--seconds", [&](const std::string& v) { o.seconds = std::stod(v); }},
       {"--count", [&](const std::string& v) { o.count = std::stoi(v); }},
       {"--cpu", [&](const std::string& v) { o.cpu = std::stoi(v); }}},
      kUsage);
  if (o.dxlemu.empty() || o.seconds <= 0 || o.count <= 0) {
    throw std::invalid_argument(kUsage);
  }
  return o;
}

}  // namespace

int main(int argc, char** argv) {
  return bench::bench_main("scale", argc, argv, parse, [](const Options& options) {
    const bench::TempDir dir("dxlemu-scale");
    const long base_kib = baseline_kib(options, dir);
    one_bus(options, dir, base_kib);
    many_ports(options, dir, base_kib);
  });
}
