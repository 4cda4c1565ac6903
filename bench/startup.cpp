// Start-up: how long `dxlemu run` takes from spawn to its readiness line, and from SIGTERM to its
// exit, against another dxlemu binary in the same run.
//
// Each round starts every binary once, one after the other, as a user or a test does:
// posix_spawn of `BINARY run --link DIR/dxl0 --log-level error ARGS`, then the readiness line
// read from its stdout ("ready": the time from just before posix_spawn to the line's newline,
// both on steady_clock), then SIGTERM and waitpid ("stop": from the kill to waitpid's return).
// With --before OLD, the rounds interleave OLD and the binary under test and take turns at going
// first, so that a change of load on a shared machine falls on both alike. Without --arg the bus
// is dxlemu's default (three XM430-W350).
//
// Reported, as a Markdown table on stdout: per binary the median, minimum and maximum of "ready"
// and the median of "stop" and of both together; then the ratios new/old of the medians, and the
// median of the per-round ratios (each round's new over the same round's old), which is the
// figure least moved by a machine whose load changes between rounds. Progress goes to stderr.
//
// Usage: startup --dxlemu PATH [--before PATH] [--rounds N] [--arg ARG]... [--cpu N]
// --arg ARG passes ARG on to `dxlemu run` (repeat it for several), e.g. --arg --servo --arg
// sts3215:1-6. --cpu N pins the bench, and every dxlemu it starts, to CPU N.
// The environment is passed on: ASAN_OPTIONS for a sanitizer build, DXLEMU_MODELS_DIR.
#include <algorithm>
#include <chrono>
#include <iostream>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "support/bench_main.hpp"
#include "support/daemon.hpp"
#include "support/flags.hpp"
#include "support/serial_port.hpp"
#include "support/stats.hpp"
#include "support/temp_dir.hpp"

namespace {

namespace bench = dxlemu::bench;
using bench::Clock;
using std::chrono::duration;
using std::chrono::nanoseconds;

constexpr double kMsPerS = 1e3;
// Milliseconds with two decimals: a Release start takes a few ms, a sanitizer one some hundred.
constexpr int kMsDecimals = 2;
constexpr int kRatioDecimals = 3;

struct Options {
  std::string dxlemu;
  std::string before;
  int rounds = 20;
  std::vector<std::string> daemon_args;  // --arg ARG: more arguments for `dxlemu run`
  int cpu = -1;
};

constexpr const char* kUsage =
    "usage: startup --dxlemu PATH [--before PATH] [--rounds N] [--arg ARG]... [--cpu N]";

Options parse(int argc, char** argv) {
  Options o;
  bench::parse_flags(argc, argv,
                     {{"--dxlemu", [&](const std::string& v) { o.dxlemu = v; }},
                      {"--before", [&](const std::string& v) { o.before = v; }},
                      {"--rounds", [&](const std::string& v) { o.rounds = std::stoi(v); }},
                      {"--arg", [&](const std::string& v) { o.daemon_args.push_back(v); }},
                      {"--cpu", [&](const std::string& v) { o.cpu = std::stoi(v); }}},
                     kUsage);
  if (o.dxlemu.empty() || o.rounds <= 0) {
    throw std::invalid_argument(kUsage);
  }
  return o;
}

double ms(nanoseconds d) {
  return duration<double>(d).count() * kMsPerS;
}

// One binary's figures, one entry per round, in ms.
struct Samples {
  std::string label;
  std::string binary;
  std::vector<double> ready;
  std::vector<double> stop;
  std::vector<double> total;
};

// One start and stop of `samples.binary`, recorded.
void measure(Samples& samples, const std::vector<std::string>& args) {
  const auto spawned = Clock::now();
  bench::Daemon daemon(samples.binary, args);
  const auto ready = Clock::now();
  const int status = daemon.stop();
  const auto stopped = Clock::now();
  if (status != 0) {
    throw std::runtime_error(samples.binary + " did not exit cleanly after SIGTERM (wait status " +
                             std::to_string(status) + ")");
  }
  samples.ready.push_back(ms(ready - spawned));
  samples.stop.push_back(ms(stopped - ready));
  samples.total.push_back(ms(stopped - spawned));
}

std::string row(const Samples& s) {
  const auto [min, max] = std::minmax_element(s.ready.begin(), s.ready.end());
  return "| " + s.label + " | " + std::to_string(s.ready.size()) + " | " +
         bench::fixed(bench::median(s.ready), kMsDecimals) + " | " +
         bench::fixed(*min, kMsDecimals) + " | " + bench::fixed(*max, kMsDecimals) + " | " +
         bench::fixed(bench::median(s.stop), kMsDecimals) + " | " +
         bench::fixed(bench::median(s.total), kMsDecimals) + " |";
}

// The median of new[i] / old[i] over the rounds.
double median_ratio(const std::vector<double>& now, const std::vector<double>& old) {
  std::vector<double> ratios;
  ratios.reserve(now.size());
  for (std::size_t i = 0; i < now.size(); ++i) {
    ratios.push_back(now[i] / old[i]);
  }
  return bench::median(ratios);
}

}  // namespace

int main(int argc, char** argv) {
  return bench::bench_main("startup", argc, argv, parse, [](const Options& options) {
    const bench::TempDir dir("dxlemu-startup");
    std::vector<std::string> args = {"--link", (dir.path() / "dxl0").string(), "--log-level",
                                     "error"};
    args.insert(args.end(), options.daemon_args.begin(), options.daemon_args.end());
    Samples now{"new: " + options.dxlemu, options.dxlemu, {}, {}, {}};
    std::optional<Samples> old;
    if (!options.before.empty()) {
      old = Samples{"old: " + options.before, options.before, {}, {}, {}};
    }
    for (int round = 0; round < options.rounds; ++round) {
      std::cerr << "startup: round " << round + 1 << " of " << options.rounds << "\n";
      // Taking turns at going first: a start right after another may find more of the files it
      // reads in the page cache, or the CPU still awake.
      if (old && round % 2 == 0) {
        measure(*old, args);
      }
      measure(now, args);
      if (old && round % 2 == 1) {
        measure(*old, args);
      }
    }
    std::cout << "| binary | rounds | spawn → ready, median (ms) | min (ms) | max (ms) | "
                 "SIGTERM → exit, median (ms) | spawn → exit, median (ms) |\n"
                 "|---|---:|---:|---:|---:|---:|---:|\n";
    if (old) {
      std::cout << row(*old) << "\n";
    }
    std::cout << row(now) << "\n";
    if (old) {
      std::cout
          << "\n| new / old | ratio of the medians | median of the per-round ratios |\n"
             "|---|---:|---:|\n"
          << "| spawn → ready | "
          << bench::fixed(bench::median(now.ready) / bench::median(old->ready), kRatioDecimals)
          << " | " << bench::fixed(median_ratio(now.ready, old->ready), kRatioDecimals) << " |\n"
          << "| spawn → exit | "
          << bench::fixed(bench::median(now.total) / bench::median(old->total), kRatioDecimals)
          << " | " << bench::fixed(median_ratio(now.total, old->total), kRatioDecimals) << " |\n";
    }
  });
}
