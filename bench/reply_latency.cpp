// Timing fidelity of the real-time driver: how far from its modelled time a reply
// reaches a client on the PTY.
//
// For each baud rate the bench starts `dxlemu run` with ten XM430-W350 (IDs 1 ~ 10, factory
// settings but the baud), reads the readiness line to learn the PTY, and sends N of each case, one
// at a time, as a controller does: Ping, Read 4 B, Write 4 B (to ID 1), Sync Read and Fast Sync
// Read of 4 B from IDs 1 ~ 6, and a broadcast Ping answered by all ten. For every round trip:
//
//   lateness = (steady_clock when the read() that completed the last reply byte returned)
//            - (steady_clock when the write() of the instruction returned + modelled time)
//   modelled = wire(instruction) + for each reply in the chain:
//              processing time + Return Delay Time + wire(reply)
//
// which is the reply timing of docs/bus.md measured from outside (a Fast Sync Read is one reply,
// charged one processing time and one Return Delay Time). Both processes read the same
// CLOCK_MONOTONIC. The first reply of each case is checked with the codec (every packet framed,
// from the expected IDs, error 0); every later one must equal it byte for byte (the servos stand
// still, so their answers do not change). The last column is the CPU time dxlemu's threads ran
// during the case (/proc/PID/task/*/schedstat) over its round trips, warm-up included: what the
// real-time driver costs per reply chain. The result is a Markdown table on stdout
// (scripts/bench.sh puts it in docs/benchmarks.md); progress goes to stderr.
//
// Usage: reply_latency --dxlemu PATH [--baud BPS]... [--count N] [--warmup N] [--cpu N]
//                      [--arg ARG]... [--echo PATH]
//        reply_latency --pty PATH --baud BPS [--count N] [--warmup N] [--cpu N]
// --arg ARG passes ARG on to `dxlemu run` (repeat it for several). The second form measures an
// emulator already serving xm430-w350 IDs 1 ~ 10 at BPS on PATH.
// --echo PATH (bench/pty_echo) adds, after dxlemu's cases at each baud rate, the Read 4 B case
// against `pty_echo --reply-after-us MODELLED`: a process that does nothing but sleep until the
// reply's modelled time and write it. Its CPU per round trip is the floor of any responder that
// keeps reply timing (one sleep for the instruction, one for the reply); dxlemu's Read 4 B row
// of the same run, divided by it, is what dxlemu costs beyond that floor.
// --cpu N pins the bench, and the dxlemu it starts, to CPU N: the reply then wakes the client on
// the CPU that sent it, which takes the cost of waking another (idle, possibly halted virtual)
// CPU out of the figures.
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <iostream>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "bus/line_timing.hpp"
#include "support/bench_main.hpp"
#include "support/daemon.hpp"
#include "support/flags.hpp"
#include "support/serial_port.hpp"
#include "support/stats.hpp"
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
namespace wire = dxlemu::wire;

constexpr const char* kServos = "xm430-w350:1-10";
constexpr std::uint8_t kServoCount = 10;
constexpr std::uint8_t kGroupSize = 6;  // Sync Read and Fast Sync Read ask IDs 1 ~ 6
using dxlemu::bench::kMaxWriteTime;
using dxlemu::bench::kPresentPosition;
using dxlemu::bench::kProcessing;
using dxlemu::bench::kReplyTimeout;
using dxlemu::bench::kReturnDelay;
using dxlemu::bench::kSettle;
// Profile Velocity (112, 4 bytes; writing 0 there changes nothing while the servo stands still),
// written as the Write case. Present Position and Profile Velocity are both 4 bytes.
constexpr std::uint16_t kProfileVelocity = 112;
constexpr std::uint16_t kItemSize = dxlemu::bench::kPresentPositionSize;

constexpr double kMedian = 0.5;
constexpr double kP99 = 0.99;

struct Options {
  std::string dxlemu;
  std::string pty;
  std::vector<std::uint32_t> bauds;
  int count = 2000;
  int warmup = 50;
  int cpu = -1;  // with --cpu N, the bench and the dxlemu it starts run on CPU N only
  std::vector<std::string> daemon_args;  // --arg ARG: more arguments for `dxlemu run`
  std::string echo;                      // --echo PATH: pty_echo, the bare timed responder
};

// One kind of round trip: the instruction, the replies it gets (one entry per packet on the
// line: the ID it comes from and its size in bytes).
struct Reply {
  std::uint8_t id;
  std::size_t size;
};
struct Case {
  std::string name;
  std::vector<std::uint8_t> instruction;
  std::vector<Reply> replies;

  std::size_t reply_bytes() const {
    std::size_t n = 0;
    for (const Reply& r : replies) {
      n += r.size;
    }
    return n;
  }
  nanoseconds modelled(std::uint32_t bps) const {
    nanoseconds t = dxlemu::bus::wire_time(instruction.size(), bps);
    for (const Reply& r : replies) {
      t += kProcessing + kReturnDelay + dxlemu::bus::wire_time(r.size, bps);
    }
    return t;
  }
};

struct Result {
  std::vector<nanoseconds> lateness;  // one per round trip after the warm-up
  int lost = 0;                       // no reply within the timeout, or not the expected one
  int skipped = 0;                    // write() took longer than kMaxWriteTime
  // dxlemu's CPU time (all threads) per round trip, warm-up included; empty without a daemon.
  std::optional<nanoseconds> cpu_per_round_trip;
};

// A 2.0 status packet's size with `params` parameter bytes: header (4), ID, LENGTH (2),
// instruction 0x55, error, parameters, CRC (2).
std::size_t status_size(std::size_t params) {
  return wire::encode_status({wire::Protocol::V2, 1, 0, std::vector<std::uint8_t>(params)}).size();
}

// True when `bytes` are exactly `c`'s replies: framed, from the expected IDs, error 0.
bool valid_replies(std::span<const std::uint8_t> bytes, const Case& c) {
  wire::Framer framer(wire::Protocol::V2);
  std::vector<wire::FramerEvent> events;
  framer.feed(bytes, dxlemu::sim::SimTime{}, events);
  if (events.size() != c.replies.size()) {
    return false;
  }
  for (std::size_t i = 0; i < events.size(); ++i) {
    const auto* frame = std::get_if<wire::Frame>(&events[i]);
    if (frame == nullptr || frame->id != c.replies[i].id ||
        frame->raw.size() != c.replies[i].size) {
      return false;
    }
    if (frame->id == wire::kBroadcastId) {
      const auto fast = wire::decode_fast_reply(*frame, std::vector<std::uint16_t>(kGroupSize, 4));
      const auto* reply = std::get_if<wire::FastReply>(&fast);
      if (reply == nullptr || std::any_of(reply->blocks.begin(), reply->blocks.end(),
                                          [](const auto& b) { return b.error != 0; })) {
        return false;
      }
    } else {
      const auto status = wire::decode_status(*frame);
      const auto* s = std::get_if<wire::StatusPacket>(&status);
      if (s == nullptr || s->error != 0) {
        return false;
      }
    }
  }
  return true;
}

Result measure(int fd, std::uint32_t bps, const Case& c, const Options& options,
               std::optional<pid_t> daemon) {
  Result r;
  const nanoseconds cpu_before = daemon ? dxlemu::bench::run_time(*daemon) : nanoseconds{0};
  const nanoseconds modelled = c.modelled(bps);
  r.lateness.reserve(static_cast<std::size_t>(options.count));
  std::vector<std::uint8_t> reply(c.reply_bytes());
  std::vector<std::uint8_t> reference;  // the first valid reply
  for (int i = 0; i < options.warmup + options.count; ++i) {
    const bool counted = i >= options.warmup;
    const Clock::time_point before = Clock::now();
    if (::write(fd, c.instruction.data(), c.instruction.size()) !=
        static_cast<ssize_t>(c.instruction.size())) {
      dxlemu::bench::fail("write");
    }
    const Clock::time_point sent = Clock::now();
    const auto got = dxlemu::bench::read_exactly(fd, reply, sent + modelled + kReplyTimeout);
    const bool valid = got && (reference.empty() ? valid_replies(reply, c) : reply == reference);
    if (valid && reference.empty()) {
      reference = reply;
    }
    if (!valid) {
      r.lost += counted ? 1 : 0;
      usleep(std::chrono::duration_cast<microseconds>(kSettle).count());
      dxlemu::bench::flush_input(fd);
    } else if (sent - before > kMaxWriteTime) {
      r.skipped += counted ? 1 : 0;
    } else if (counted) {
      r.lateness.push_back(*got - (sent + modelled));
    }
  }
  if (daemon) {
    r.cpu_per_round_trip =
        (dxlemu::bench::run_time(*daemon) - cpu_before) / (options.warmup + options.count);
  }
  return r;
}

void print_row(std::uint32_t bps, const Case& c, Result r) {
  using dxlemu::bench::us;
  std::sort(r.lateness.begin(), r.lateness.end());
  std::cout << "| " << bps << " | " << c.name << " | " << r.lateness.size() << " | " << r.lost
            << " | " << r.skipped << " | " << us(c.modelled(bps)) << " | ";
  if (r.lateness.empty()) {
    std::cout << "- | - | - | - | ";
  } else {
    std::cout << us(r.lateness.front()) << " | "
              << us(dxlemu::bench::percentile(r.lateness, kMedian)) << " | "
              << us(dxlemu::bench::percentile(r.lateness, kP99)) << " | " << us(r.lateness.back())
              << " | ";
  }
  if (r.cpu_per_round_trip) {
    std::cout << us(*r.cpu_per_round_trip) << " |" << std::endl;
  } else {
    std::cout << "- |" << std::endl;
  }
}

std::vector<Case> cases() {
  using wire::Protocol;
  const std::uint8_t one = 1;
  const std::size_t ping_status = status_size(dxlemu::bench::kPingParams);
  const std::size_t read_status = status_size(kItemSize);
  std::vector<std::uint8_t> group;
  std::vector<Reply> group_replies;
  wire::FastReply fast;
  for (std::uint8_t id = 1; id <= kGroupSize; ++id) {
    group.push_back(id);
    group_replies.push_back({id, read_status});
    fast.blocks.push_back({0, id, std::vector<std::uint8_t>(kItemSize)});
  }
  std::vector<Reply> all_pings;
  for (std::uint8_t id = 1; id <= kServoCount; ++id) {
    all_pings.push_back({id, ping_status});
  }
  return {
      {"Ping", wire::encode_instruction({Protocol::V2, one, wire::Ping{}}), {{one, ping_status}}},
      {"Read 4 B",
       wire::encode_instruction({Protocol::V2, one, wire::Read{kPresentPosition, kItemSize}}),
       {{one, read_status}}},
      {"Write 4 B",
       wire::encode_instruction(
           {Protocol::V2, one,
            wire::Write{kProfileVelocity, std::vector<std::uint8_t>(kItemSize)}}),
       {{one, status_size(0)}}},
      {"Sync Read 4 B × 6",
       wire::encode_instruction(
           {Protocol::V2, wire::kBroadcastId, wire::SyncRead{kPresentPosition, kItemSize, group}}),
       group_replies},
      {"Fast Sync Read 4 B × 6",
       wire::encode_instruction({Protocol::V2, wire::kBroadcastId,
                                 wire::FastSyncRead{{kPresentPosition, kItemSize, group}}}),
       {{wire::kBroadcastId, wire::encode_fast_reply(fast).size()}}},
      {"broadcast Ping × 10",
       wire::encode_instruction({Protocol::V2, wire::kBroadcastId, wire::Ping{}}), all_pings},
  };
}

// The case pty_echo answers (its canned status is this one's reply).
constexpr std::string_view kEchoCase = "Read 4 B";

// The Read 4 B case against pty_echo answering at the modelled time: the bare timed responder.
void measure_echo(std::uint32_t bps, const Options& options) {
  const std::vector<Case> all = cases();
  Case read =
      *std::find_if(all.begin(), all.end(), [](const Case& c) { return c.name == kEchoCase; });
  const auto delay = std::chrono::round<microseconds>(read.modelled(bps));
  dxlemu::bench::Daemon echo(
      std::vector<std::string>{options.echo, "--reply-after-us", std::to_string(delay.count())});
  const int fd = dxlemu::bench::open_port(echo.pty(), bps);
  read.name += ", bare timed responder";
  std::cerr << "reply_latency: " << read.name << " at " << bps << " bit/s\n";
  print_row(bps, read, measure(fd, bps, read, options, echo.pid()));
  ::close(fd);
}

constexpr const char* kUsage =
    "usage: reply_latency --dxlemu PATH [--baud BPS]... [--count N] [--warmup N] [--cpu N] "
    "[--arg ARG]... [--echo PATH]\n"
    "       reply_latency --pty PATH --baud BPS [--count N] [--warmup N] [--cpu N]";

Options parse(int argc, char** argv) {
  Options o;
  dxlemu::bench::parse_flags(argc, argv,
                             {{"--dxlemu", [&](const std::string& v) { o.dxlemu = v; }},
                              {"--pty", [&](const std::string& v) { o.pty = v; }},
                              {"--baud",
                               [&](const std::string& v) {
                                 o.bauds.push_back(static_cast<std::uint32_t>(std::stoul(v)));
                               }},
                              {"--count", [&](const std::string& v) { o.count = std::stoi(v); }},
                              {"--warmup", [&](const std::string& v) { o.warmup = std::stoi(v); }},
                              {"--cpu", [&](const std::string& v) { o.cpu = std::stoi(v); }},
                              {"--arg", [&](const std::string& v) { o.daemon_args.push_back(v); }},
                              {"--echo", [&](const std::string& v) { o.echo = v; }}},
                             kUsage);
  if (o.dxlemu.empty() == o.pty.empty() || (!o.pty.empty() && o.bauds.size() != 1) ||
      o.count <= 0 || o.warmup < 0 || (!o.echo.empty() && o.dxlemu.empty())) {
    throw std::invalid_argument(kUsage);
  }
  if (o.bauds.empty()) {
    o.bauds = {57'600, 1'000'000, 4'000'000};
  }
  return o;
}

}  // namespace

int main(int argc, char** argv) {
  return dxlemu::bench::bench_main("reply_latency", argc, argv, parse, [](const Options& options) {
    std::cout << "| baud | instruction | round trips | lost | skipped | modelled (µs) | min (µs) | "
                 "median (µs) | p99 (µs) | max (µs) | dxlemu CPU per round trip (µs) |\n"
                 "|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|"
              << std::endl;
    for (const std::uint32_t bps : options.bauds) {
      std::optional<dxlemu::bench::Daemon> daemon;
      if (!options.dxlemu.empty()) {
        const std::string link = "/tmp/dxlemu-bench-" + std::to_string(getpid());
        std::vector<std::string> args = {"--servo",           kServos,  "--baud",
                                         std::to_string(bps), "--link", link};
        args.insert(args.end(), options.daemon_args.begin(), options.daemon_args.end());
        daemon.emplace(options.dxlemu, args);
      }
      const int fd = dxlemu::bench::open_port(daemon ? daemon->pty() : options.pty, bps);
      for (const Case& c : cases()) {
        std::cerr << "reply_latency: " << c.name << " at " << bps << " bit/s\n";
        print_row(bps, c,
                  measure(fd, bps, c, options,
                          daemon ? std::optional<pid_t>(daemon->pid()) : std::nullopt));
      }
      ::close(fd);
      if (!options.echo.empty()) {
        measure_echo(bps, options);
      }
    }
  });
}
