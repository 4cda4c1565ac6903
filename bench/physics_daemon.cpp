// Physics cost: a robot arm's servos on its MuJoCo world at the default 1 kHz motion tick, in the
// real daemon under realtime timing, against the same bus without the world.
//
// Each round starts `dxlemu run --robot ROBOT` twice, once with `--physics PHYSICS` and once
// without (the order alternates between rounds, so drift of the machine hits both alike), and
// for D seconds drives it as a controller would: every servo's torque on, then every 10 ms a
// `list` through the control API (every servo's Present Position, as a 100 Hz state read), and
// every second new goals, alternately home + SWING and home - SWING pulses for every servo, so
// every joint moves and carries its links. Measured per run, over the D seconds:
//
//   CPU share   = the daemon's run time (/proc/PID/task/*/schedstat) / wall time, in % of a CPU;
//   world lag   = simulated time (clock.now) - the world's time (physics.time_ms) at the end:
//                 what the world had not yet stepped (the daemon catches it up every 10 ms);
//   moved       = the largest distance any servo's Present Position travelled (pulses), to show
//                 that the arm moved in both runs.
//
// "Real time" holds when the world lag stays under the daemon's 10 ms catch-up period: every
// tick of the world ran on time. Markdown to stdout, progress to stderr.
//
// Usage: physics_daemon --dxlemu PATH [--robot NAME] [--physics NAME] [--seconds D] [--rounds R]
//                    [--swing PULSES] [--cpu N]
#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "support/bench_main.hpp"
#include "support/control_socket.hpp"
#include "support/daemon.hpp"
#include "support/flags.hpp"
#include "support/stats.hpp"
#include "support/temp_dir.hpp"

namespace {

namespace bench = dxlemu::bench;
using bench::Clock;
using dxlemu::bench::fixed;
using nlohmann::json;
using std::chrono::milliseconds;
using std::chrono::nanoseconds;

constexpr const char* kUsage =
    "usage: physics_daemon --dxlemu PATH [--robot NAME] [--physics NAME] [--seconds D] "
    "[--rounds R] [--swing PULSES] [--cpu N]";
constexpr milliseconds kReadPeriod{10};
constexpr milliseconds kGoalPeriod{1000};
constexpr auto kControlTimeout = std::chrono::seconds(10);
constexpr double kPercent = 100.0;

struct Options {
  std::string dxlemu;
  std::string robot = "so101-follower";
  std::string physics = "so101-follower";
  double seconds = 10;
  int rounds = 3;
  int swing = 300;
  int cpu = -1;
};

Options parse(int argc, char** argv) {
  Options o;
  bench::parse_flags(argc, argv,
                     {{"--dxlemu", [&](const std::string& v) { o.dxlemu = v; }},
                      {"--robot", [&](const std::string& v) { o.robot = v; }},
                      {"--physics", [&](const std::string& v) { o.physics = v; }},
                      {"--seconds", [&](const std::string& v) { o.seconds = std::stod(v); }},
                      {"--rounds", [&](const std::string& v) { o.rounds = std::stoi(v); }},
                      {"--swing", [&](const std::string& v) { o.swing = std::stoi(v); }},
                      {"--cpu", [&](const std::string& v) { o.cpu = std::stoi(v); }}},
                     kUsage);
  if (o.dxlemu.empty() || o.seconds <= 0 || o.rounds <= 0 || o.swing <= 0) {
    throw std::invalid_argument(kUsage);
  }
  return o;
}

// One control connection's requests, each checked for "ok".
class Control {
 public:
  explicit Control(const std::string& path) : connection_(path) {}

  json call(const json& request) {
    const json reply =
        json::parse(connection_.call(request.dump(), Clock::now() + kControlTimeout));
    if (!reply.value("ok", false)) {
      throw std::runtime_error(request.dump() + " -> " + reply.dump());
    }
    return reply["result"];
  }

 private:
  bench::ControlConnection connection_;
};

struct Run {
  double cpu_percent = 0;
  double world_lag_ms = 0;  // physics runs only
  double moved = 0;         // pulses
};

// The item that switches a servo's torque: DYNAMIXEL's Torque Enable or FEETECH's Torque Switch.
std::string torque_item(Control& control, const std::string& port, int id) {
  for (const char* key : {"torque_enable", "torque_switch"}) {
    const json probe = {{"cmd", "get"}, {"port", port}, {"servo", id}, {"item", key}};
    try {
      control.call(probe);
      return key;
    } catch (const std::runtime_error&) {
      // Not this maker's name: try the other.
    }
  }
  throw std::runtime_error("servo " + std::to_string(id) + " has no torque item");
}

Run measure(const Options& options, bool physics, const bench::TempDir& dir) {
  const std::string control_path = (dir.path() / "control.sock").string();
  std::vector<std::string> args = {
      "--robot",   options.robot, "--link",      (dir.path() / "arm").string(),
      "--control", control_path,  "--log-level", "warn"};
  if (physics) {
    args.insert(args.end(), {"--physics", options.physics});
  }
  bench::Daemon daemon(options.dxlemu, args);
  Control control(control_path);
  const std::string port = daemon.ready().front()["port"];
  std::vector<int> ids;
  for (const json& servo : daemon.ready().front()["servos"]) {
    ids.push_back(servo["id"]);
  }
  std::map<int, std::int64_t> home;
  std::map<int, std::pair<std::int64_t, std::int64_t>> range;  // lowest, highest seen
  // Each `list` result is kept in a variable: a range-for over a member of a temporary would
  // dangle.
  const json listed = control.call({{"cmd", "list"}});
  for (const json& servo : listed["ports"][0]["servos"]) {
    home[servo["id"]] = servo["present_position"];
  }
  const std::string torque = torque_item(control, port, ids.front());
  for (const int id : ids) {
    control.call({{"cmd", "set"}, {"port", port}, {"servo", id}, {"item", torque}, {"value", 1}});
  }

  const nanoseconds run_start = bench::run_time(daemon.pid());
  const auto start = Clock::now();
  const auto end = start + std::chrono::duration_cast<Clock::duration>(
                               std::chrono::duration<double>(options.seconds));
  auto next_read = start;
  auto next_goal = start;
  int sign = 1;
  while (Clock::now() < end) {
    const auto now = Clock::now();
    if (now >= next_goal) {
      for (const int id : ids) {
        control.call({{"cmd", "set"},
                      {"port", port},
                      {"servo", id},
                      {"item", "goal_position"},
                      {"value", home[id] + static_cast<std::int64_t>(sign) * options.swing}});
      }
      sign = -sign;
      next_goal += kGoalPeriod;
    }
    const json state = control.call({{"cmd", "list"}});
    for (const json& servo : state["ports"][0]["servos"]) {
      const std::int64_t p = servo["present_position"];
      auto [it, fresh] = range.try_emplace(servo["id"].get<int>(), p, p);
      it->second = {std::min(it->second.first, p), std::max(it->second.second, p)};
    }
    next_read += kReadPeriod;
    std::this_thread::sleep_until(next_read);
  }
  const auto wall = Clock::now() - start;
  const nanoseconds run = bench::run_time(daemon.pid()) - run_start;

  Run out;
  out.cpu_percent = kPercent * static_cast<double>(run.count()) /
                    static_cast<double>(std::chrono::duration_cast<nanoseconds>(wall).count());
  if (physics) {
    // Read the world's time before the clock: the clock reads later, so the lag is not
    // understated.
    const double world_ms = control.call({{"cmd", "physics"}})["time_ms"];
    const double now_ms = control.call({{"cmd", "clock.now"}})["ms"];
    out.world_lag_ms = now_ms - world_ms;
  }
  for (const auto& [id, seen] : range) {
    out.moved = std::max(out.moved, static_cast<double>(seen.second - seen.first));
  }
  daemon.stop();
  return out;
}

void report(const Options& options, const std::vector<Run>& with, const std::vector<Run>& without) {
  std::vector<double> cpu_with;
  std::vector<double> cpu_without;
  std::vector<double> ratio;
  std::vector<double> lag;
  for (std::size_t i = 0; i < with.size(); ++i) {
    cpu_with.push_back(with[i].cpu_percent);
    cpu_without.push_back(without[i].cpu_percent);
    ratio.push_back(with[i].cpu_percent / without[i].cpu_percent);
    lag.push_back(with[i].world_lag_ms);
  }
  std::cout << "### " << options.robot << " with --physics " << options.physics << ", "
            << options.rounds << " rounds of " << fixed(options.seconds, 0)
            << " s, realtime, 1 kHz motion tick\n\n"
            << "| round | CPU with physics (%) | CPU without (%) | ratio | world lag at end (ms) "
               "| moved with / without (pulses) |\n"
            << "|---|---|---|---|---|---|\n";
  for (std::size_t i = 0; i < with.size(); ++i) {
    std::cout << "| " << i + 1 << " | " << fixed(with[i].cpu_percent, 1) << " | "
              << fixed(without[i].cpu_percent, 1) << " | " << fixed(ratio[i], 2) << " | "
              << fixed(with[i].world_lag_ms, 1) << " | " << fixed(with[i].moved, 0) << " / "
              << fixed(without[i].moved, 0) << " |\n";
  }
  std::cout << "| median | " << fixed(bench::median(cpu_with), 1) << " | "
            << fixed(bench::median(cpu_without), 1) << " | " << fixed(bench::median(ratio), 2)
            << " | " << fixed(bench::median(lag), 1) << " | |\n\n";
}

}  // namespace

int main(int argc, char** argv) {
  return bench::bench_main("physics_daemon", argc, argv, parse, [](const Options& options) {
    const bench::TempDir dir("dxlemu-physics");
    std::vector<Run> with;
    std::vector<Run> without;
    for (int round = 0; round < options.rounds; ++round) {
      // Alternate which goes first, so that a trend of the machine's load hits both alike.
      for (const bool physics :
           round % 2 == 0 ? std::vector{true, false} : std::vector{false, true}) {
        std::cerr << "round " << round + 1 << ": " << (physics ? "with" : "without")
                  << " physics\n";
        (physics ? with : without).push_back(measure(options, physics, dir));
      }
    }
    report(options, with, without);
  });
}
