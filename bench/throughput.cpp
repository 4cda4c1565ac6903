// Throughput: how many round trips per second a client gets from dxlemu
// under `--timing fast`, against a bare PTY program that does no work (the physical limit), and
// what the trace, the capture and the control API cost.
//
// Targets, each started afresh for every run (bench::Daemon, readiness line read):
//
//   pty echo                    bench/pty_echo: reads 14 bytes, writes a canned 15-byte status
//   dxlemu                      dxlemu run --timing fast --servo xm430-w350:1
//   dxlemu + trace file         the same with --trace FILE (a temporary file)
//   dxlemu + pcap file          the same with --pcap FILE
//   dxlemu + trace subscriber   the same with a control client subscribed to trace events
//                               (trace.subscribe), reading and discarding them in a thread
//   dxlemu + stats client       the same with a control client sending `stats` requests, one at
//                               a time, as fast as it can, in a thread
//
// The client opens the PTY raw at 57600 bit/s (the XM430-W350's factory rate: a servo answers
// only a client at its rate; pty_echo ignores it) and sends Read of Present Position (ID 1,
// address 132, 4 bytes), one at a time, each waiting in poll(2) for the full 15-byte status, for
// a warm-up and then for D seconds. Every status must equal the one an XM430-W350 standing at
// 2048 sends (built with the codec): one that differs counts as wrong, one not complete within
// 100 ms as lost; neither counts as a round trip. Per run: good round trips per second, mean, p99
// and max round-trip time (from before write() to the return of the read() that completed the
// status), the daemon's CPU use over the measured seconds (bench::cpu_time, user + system, per
// wall second: 100 % is one CPU) and per round trip, the ratio of round trips per second to
// pty_echo's in the same round, and what the side load did.
//
// Runs are interleaved (echo, dxlemu, + trace, ..., echo, dxlemu, ...) so that the machine's load
// falls on every target alike. The result is two Markdown tables on stdout, the medians and every
// run; progress goes to stderr.
//
// Usage: throughput --dxlemu PATH --echo PATH [--seconds D] [--runs R] [--cpu N] [--target NAME]...
//                   [--baseline PATH]
// --cpu N pins the bench, its threads and the daemons it starts to CPU N. --target NAME (a name
// above, e.g. --target "dxlemu + trace file") measures only the targets named, and pty echo.
// --baseline PATH adds the target "baseline dxlemu": the plain dxlemu target run with another
// binary (e.g. the last release's), interleaved with the others, so that a change is measured
// against what it changes in the same run.
#include <unistd.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <iostream>
#include <memory>
#include <numeric>
#include <optional>
#include <stdexcept>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "support/bench_main.hpp"
#include "support/control_socket.hpp"
#include "support/daemon.hpp"
#include "support/flags.hpp"
#include "support/read_position.hpp"
#include "support/serial_port.hpp"
#include "support/stats.hpp"

namespace {

namespace bench = dxlemu::bench;
using bench::Clock;
using dxlemu::bench::fixed;
using std::chrono::milliseconds;
using std::chrono::nanoseconds;

constexpr std::uint8_t kServoId = 1;
// The XM430-W350's factory Baud Rate; dxlemu's servo answers only a client at its rate.
constexpr std::uint32_t kBaud = 57'600;
// Round trips before the measured seconds: the daemon's first replies (page faults, caches, the
// control client connecting) are not what a long-running client sees.
constexpr milliseconds kWarmup{500};
using dxlemu::bench::kReplyTimeout;  // a fast reply takes tens of µs
using dxlemu::bench::kSettle;
// How long a control client waits for a reply, and how often the subscriber looks at the
// stop flag while no event comes.
constexpr milliseconds kControlTimeout{5000};
constexpr milliseconds kSubscriberPoll{50};

constexpr double kP99 = 0.99;
constexpr double kPercent = 100.0;

struct Options {
  std::string dxlemu;
  std::string echo;
  double seconds = 5;
  int runs = 3;
  int cpu = -1;  // with --cpu N, the bench, its threads and the daemons run on CPU N only
  std::vector<std::string> only;  // --target NAME...: these targets (and pty echo) only
  std::string baseline;           // --baseline PATH: a second dxlemu binary to measure
};

// What runs beside the bus client while it measures.
enum class SideLoad { None, Subscriber, StatsClient };

struct Target {
  std::string name;
  bool echo = false;          // pty_echo instead of dxlemu
  std::string output_option;  // "--trace" or "--pcap" (to a temporary file), or none
  SideLoad load = SideLoad::None;
  bool baseline = false;  // runs the --baseline binary
};

constexpr const char* kBaselineTarget = "baseline dxlemu";

std::vector<Target> targets(const Options& options) {
  std::vector<Target> out = {
      {"pty echo", true, "", SideLoad::None},
      {"dxlemu", false, "", SideLoad::None},
      {"dxlemu + trace file", false, "--trace", SideLoad::None},
      {"dxlemu + pcap file", false, "--pcap", SideLoad::None},
      {"dxlemu + trace subscriber", false, "", SideLoad::Subscriber},
      {"dxlemu + stats client", false, "", SideLoad::StatsClient},
  };
  if (!options.baseline.empty()) {
    out.insert(out.begin() + 2, {kBaselineTarget, false, "", SideLoad::None, true});
  }
  return out;
}

// The figures of one run of one target (or their medians).
struct Run {
  double per_second = 0;  // good round trips per second
  nanoseconds mean{0};
  nanoseconds p99{0};
  nanoseconds max{0};
  int lost = 0;               // no complete status within kReplyTimeout
  int wrong = 0;              // a status other than the expected one
  double cpu = 0;             // the daemon's CPU time per wall second
  nanoseconds cpu_per_rt{0};  // the daemon's CPU time per good round trip
  // What the side load did over the measured seconds: bytes written per round trip (trace,
  // pcap), events received per round trip (subscriber), requests answered per second (stats).
  std::optional<double> side;
};

// Temporary paths of this bench process, so that concurrent benches and a user's dxlemu on the
// default paths are left alone.
struct Paths {
  std::filesystem::path link;
  std::filesystem::path control;
  std::filesystem::path output;

  Paths() {
    const std::filesystem::path dir = std::filesystem::temp_directory_path();
    const std::string base = "dxlemu-throughput-" + std::to_string(getpid());
    link = dir / (base + "-dxl0");
    control = dir / (base + ".sock");
    output = dir / (base + ".out");
  }
};

// A thread of the bench that loads the control API while the bus client measures: counts what it
// did (events received, requests answered) in `done`, stops when asked, and hands on a failure.
class SideClient {
 public:
  SideClient(SideLoad load, const std::string& control) {
    if (load == SideLoad::None) {
      return;
    }
    // Connected and, for the subscriber, subscribed before the bus client starts.
    auto connection = std::make_shared<bench::ControlConnection>(control);
    if (load == SideLoad::Subscriber) {
      expect_ok(
          connection->call(R"({"id":1,"cmd":"trace.subscribe"})", Clock::now() + kControlTimeout));
    }
    thread_ = std::thread([this, load, connection] {
      try {
        while (!stop_.load(std::memory_order_relaxed)) {
          if (load == SideLoad::Subscriber) {
            done_ += connection->discard_lines(Clock::now() + kSubscriberPoll);
          } else {
            expect_ok(
                connection->call(R"({"id":1,"cmd":"stats"})", Clock::now() + kControlTimeout));
            ++done_;
          }
        }
      } catch (...) {
        error_ = std::current_exception();
      }
    });
  }
  /// Stops the thread (a failure goes unreported: call finish() to hear of it).
  ~SideClient() {
    stop_ = true;
    if (thread_.joinable()) {
      thread_.join();
    }
  }
  SideClient(const SideClient&) = delete;
  SideClient& operator=(const SideClient&) = delete;

  /// Events received or requests answered so far.
  std::size_t done() const { return done_.load(); }

  /// Stops the thread; rethrows what made it fail, if anything did.
  void finish() {
    stop_ = true;
    if (thread_.joinable()) {
      thread_.join();
    }
    if (error_) {
      std::rethrow_exception(std::exchange(error_, nullptr));
    }
  }

 private:
  static void expect_ok(const std::string& reply) {
    if (reply.find(R"("ok":true)") == std::string::npos) {
      throw std::runtime_error("control request refused: " + reply);
    }
  }

  std::thread thread_;
  std::atomic<bool> stop_ = false;
  std::atomic<std::size_t> done_ = 0;
  std::exception_ptr error_;
};

// The size of the file at `path` so far; 0 when there is none (no --trace or --pcap).
std::uintmax_t size_so_far(const std::filesystem::path& path) {
  std::error_code ec;
  const std::uintmax_t size = std::filesystem::file_size(path, ec);
  return ec ? 0 : size;
}

// `bytes` as "FF FF FD ...".
std::string hex_bytes(const std::vector<std::uint8_t>& bytes) {
  std::string text;
  for (const std::uint8_t b : bytes) {
    std::array<char, 4> cell{};
    std::snprintf(cell.data(), cell.size(), "%02X ", b);
    text += cell.data();
  }
  return text.substr(0, text.size() - 1);
}

Run measure(const Target& target, const Options& options, const Paths& paths) {
  std::optional<bench::Daemon> daemon;
  if (target.echo) {
    daemon.emplace(std::vector<std::string>{options.echo});
  } else {
    std::vector<std::string> args = {"--timing",    "fast",
                                     "--servo",     "xm430-w350:1",
                                     "--link",      paths.link.string(),
                                     "--control",   paths.control.string(),
                                     "--log-level", "warn"};
    if (!target.output_option.empty()) {
      args.insert(args.end(), {target.output_option, paths.output.string()});
    }
    daemon.emplace(target.baseline ? options.baseline : options.dxlemu, args);
  }
  std::cerr << "throughput: " << target.name << " (pid " << daemon->pid() << ")\n";
  SideClient side(target.load, paths.control);
  const int fd = bench::open_port(daemon->pty(), kBaud);
  const std::vector<std::uint8_t> instruction = bench::read_position_instruction(kServoId);
  const std::vector<std::uint8_t> expected =
      bench::read_position_status(kServoId, bench::kStartPosition);
  std::vector<std::uint8_t> reply(expected.size());

  Run run;
  std::vector<nanoseconds> times;
  times.reserve(static_cast<std::size_t>(options.seconds * 100'000));  // no reallocation inside
  const auto measure_from = Clock::now() + kWarmup;
  const auto measure_for =
      std::chrono::duration_cast<nanoseconds>(std::chrono::duration<double>(options.seconds));
  std::optional<Clock::time_point> started;
  nanoseconds cpu_at_start{0};
  std::uintmax_t bytes_at_start = 0;
  std::size_t side_at_start = 0;
  bool shown = false;  // a wrong status is shown once, on stderr
  for (;;) {
    const Clock::time_point before = Clock::now();
    if (!started && before >= measure_from) {
      started = before;
      cpu_at_start = bench::cpu_time(daemon->pid());
      bytes_at_start = size_so_far(paths.output);
      side_at_start = side.done();
    }
    if (started && before - *started >= measure_for) {
      break;
    }
    if (::write(fd, instruction.data(), instruction.size()) !=
        static_cast<ssize_t>(instruction.size())) {
      bench::fail("write");
    }
    const auto got = bench::read_exactly(fd, reply, before + kReplyTimeout);
    if (!got || reply != expected) {
      if (started) {
        ++(got ? run.wrong : run.lost);
      }
      if (got && !std::exchange(shown, true)) {
        std::cerr << "throughput: " << target.name << " answered " << hex_bytes(reply) << ", not "
                  << hex_bytes(expected) << "\n";
      }
      usleep(std::chrono::duration_cast<std::chrono::microseconds>(kSettle).count());
      bench::flush_input(fd);
    } else if (started) {
      times.push_back(*got - before);
    }
  }
  const auto wall = std::chrono::duration<double>(Clock::now() - *started).count();
  const auto cpu = std::chrono::duration<double>(bench::cpu_time(daemon->pid()) - cpu_at_start);
  const std::size_t side_done = side.done() - side_at_start;
  const std::uintmax_t bytes = size_so_far(paths.output) - bytes_at_start;
  ::close(fd);
  side.finish();
  daemon->stop();
  std::filesystem::remove(paths.output);

  run.per_second = static_cast<double>(times.size()) / wall;
  run.cpu = cpu.count() / wall;
  if (!times.empty()) {
    run.cpu_per_rt = std::chrono::duration_cast<nanoseconds>(cpu) / times.size();
    run.mean = std::accumulate(times.begin(), times.end(), nanoseconds{0}) /
               static_cast<long>(times.size());
    std::sort(times.begin(), times.end());
    run.p99 = bench::percentile(times, kP99);
    run.max = times.back();
  }
  const double per_round_trip = times.empty() ? 0 : 1.0 / static_cast<double>(times.size());
  if (!target.output_option.empty()) {
    run.side = static_cast<double>(bytes) * per_round_trip;
  } else if (target.load == SideLoad::Subscriber) {
    run.side = static_cast<double>(side_done) * per_round_trip;
  } else if (target.load == SideLoad::StatsClient) {
    run.side = static_cast<double>(side_done) / wall;
  }
  return run;
}

// The side column: what the side load did, with its unit.
std::string side_text(const Target& target, std::optional<double> side) {
  if (!side) {
    return "-";
  }
  if (!target.output_option.empty()) {
    return fixed(*side, 0) + " B/round trip written";
  }
  if (target.load == SideLoad::Subscriber) {
    return fixed(*side, 2) + " events/round trip";
  }
  return fixed(*side, 0) + " stats requests/s";
}

// The medians of `runs`' figures; lost and wrong replies are summed.
Run medians(const std::vector<Run>& runs) {
  const auto median_of = [&](auto field) {
    std::vector<double> values;
    values.reserve(runs.size());
    for (const Run& run : runs) {
      values.push_back(field(run));
    }
    return bench::median(values);
  };
  const auto ns = [](double v) { return nanoseconds(std::llround(v)); };
  Run m;
  m.per_second = median_of([](const Run& r) { return r.per_second; });
  m.mean = ns(median_of([](const Run& r) { return static_cast<double>(r.mean.count()); }));
  m.p99 = ns(median_of([](const Run& r) { return static_cast<double>(r.p99.count()); }));
  m.max = ns(median_of([](const Run& r) { return static_cast<double>(r.max.count()); }));
  m.cpu = median_of([](const Run& r) { return r.cpu; });
  m.cpu_per_rt =
      ns(median_of([](const Run& r) { return static_cast<double>(r.cpu_per_rt.count()); }));
  for (const Run& run : runs) {
    m.lost += run.lost;
    m.wrong += run.wrong;
  }
  if (runs.front().side) {
    m.side = median_of([](const Run& r) { return r.side.value_or(0); });
  }
  return m;
}

void print_header(const std::string& second_column) {
  std::cout
      << "| target | " << second_column
      << " | round trips/s | ratio to pty echo | mean RTT (µs) | p99 RTT (µs) | max RTT (µs) | "
         "lost | wrong | daemon CPU (%) | daemon CPU per round trip (µs) | side load |\n"
         "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|\n";
}

void print_row(const Target& target, const std::string& second, const Run& run, double ratio) {
  std::cout << "| " << target.name << " | " << second << " | " << fixed(run.per_second, 0) << " | "
            << fixed(ratio, 2) << " | " << bench::us(run.mean) << " | " << bench::us(run.p99)
            << " | " << bench::us(run.max) << " | " << run.lost << " | " << run.wrong << " | "
            << fixed(run.cpu * kPercent, 1) << " | " << bench::us(run.cpu_per_rt) << " | "
            << side_text(target, run.side) << " |\n";
}

// results[round][target]. A run's ratio is to pty_echo's run of the same round (target 0); the
// medians' ratio is the median of those, which the interleaving makes fairer than a ratio of
// medians.
void print_tables(const std::vector<Target>& all, const std::vector<std::vector<Run>>& results) {
  print_header("runs");
  for (std::size_t t = 0; t < all.size(); ++t) {
    std::vector<Run> runs;
    std::vector<double> ratios;
    for (const auto& round : results) {
      runs.push_back(round[t]);
      ratios.push_back(round[t].per_second / round[0].per_second);
    }
    print_row(all[t], std::to_string(runs.size()), medians(runs), bench::median(ratios));
  }
  std::cout << "\nEvery run:\n\n";
  print_header("run");
  for (std::size_t t = 0; t < all.size(); ++t) {
    for (std::size_t r = 0; r < results.size(); ++r) {
      print_row(all[t], std::to_string(r + 1), results[r][t],
                results[r][t].per_second / results[r][0].per_second);
    }
  }
  std::cout << std::flush;
}

// The targets of `options`: every one, or pty echo (the reference of every ratio), the baseline
// and those named by --target.
std::vector<Target> chosen(const Options& options) {
  std::vector<Target> all = targets(options);
  if (options.only.empty()) {
    return all;
  }
  for (const std::string& name : options.only) {
    if (std::none_of(all.begin(), all.end(), [&](const Target& t) { return t.name == name; })) {
      std::string names;
      for (const Target& t : all) {
        names += (names.empty() ? "" : ", ") + t.name;
      }
      throw std::invalid_argument("no target \"" + name + "\" (targets: " + names + ")");
    }
  }
  std::erase_if(all, [&](const Target& t) {
    return !t.echo && !t.baseline &&
           std::find(options.only.begin(), options.only.end(), t.name) == options.only.end();
  });
  return all;
}

constexpr const char* kUsage =
    "usage: throughput --dxlemu PATH --echo PATH [--seconds D] [--runs R] [--cpu N]\n"
    "                  [--target NAME]... [--baseline PATH]";

Options parse(int argc, char** argv) {
  Options o;
  bench::parse_flags(argc, argv,
                     {{"--dxlemu", [&](const std::string& v) { o.dxlemu = v; }},
                      {"--echo", [&](const std::string& v) { o.echo = v; }},
                      {"--seconds", [&](const std::string& v) { o.seconds = std::stod(v); }},
                      {"--runs", [&](const std::string& v) { o.runs = std::stoi(v); }},
                      {"--cpu", [&](const std::string& v) { o.cpu = std::stoi(v); }},
                      {"--target", [&](const std::string& v) { o.only.push_back(v); }},
                      {"--baseline", [&](const std::string& v) { o.baseline = v; }}},
                     kUsage);
  if (o.dxlemu.empty() || o.echo.empty() || !(o.seconds > 0) || o.runs <= 0) {
    throw std::invalid_argument(kUsage);
  }
  return o;
}

}  // namespace

int main(int argc, char** argv) {
  return bench::bench_main("throughput", argc, argv, parse, [](const Options& options) {
    const Paths paths;
    const std::vector<Target> all = chosen(options);
    std::vector<std::vector<Run>> results;
    for (int r = 0; r < options.runs; ++r) {
      std::cerr << "throughput: round " << r + 1 << " of " << options.runs << "\n";
      auto& round = results.emplace_back();
      for (const Target& target : all) {
        round.push_back(measure(target, options, paths));
      }
    }
    print_tables(all, results);
  });
}
