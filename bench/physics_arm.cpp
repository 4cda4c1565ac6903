// Physics cost: the six STS3215 of the SO-101 follower (robots/so101-follower.json) on the
// MuJoCo world of robots/physics/so101-follower.json, against the same six servos without
// physics, in one process on the virtual clock (no PTY, no daemon).
//
// Each run simulates S seconds at the default 1 kHz motion tick: every servo in position control,
// all six goals switching between two poses every 0.5 s (so the arm is moving most of the time),
// time caught up 10 ms at a time (the daemon's physics catch-up period) with every servo read
// after each catch-up. A round is one run with physics and one without, interleaved, so that both
// see the same machine load; R rounds. Reported per variant (median over the rounds): wall time
// per simulated second, the real-time factor (simulated over wall time), the CPU time of the
// bench's thread per simulated second and over its wall time (CLOCK_THREAD_CPUTIME_ID: near
// 100 % unless the machine is busy, when the CPU figures are the ones to read); then the median
// ratios physics / no physics of wall and CPU time.
// The daemon under a controller is measured by bench/physics_daemon.
//
// Usage: physics_arm [--seconds S] [--rounds R] [--cpu N]
#include <time.h>

#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <numbers>
#include <string>
#include <vector>

#include "arm_rig.hpp"
#include "support/bench_main.hpp"
#include "support/flags.hpp"
#include "support/stats.hpp"

using namespace dxlemu;

namespace {

struct Options {
  double seconds = 10;
  int rounds = 5;
  int cpu = -1;
};

Options parse(int argc, char** argv) {
  Options o;
  bench::parse_flags(argc, argv,
                     {{"--seconds", [&](const std::string& v) { o.seconds = std::stod(v); }},
                      {"--rounds", [&](const std::string& v) { o.rounds = std::stoi(v); }},
                      {"--cpu", [&](const std::string& v) { o.cpu = std::stoi(v); }}},
                     "usage: physics_arm [--seconds S] [--rounds R] [--cpu N]");
  if (o.seconds <= 0 || o.rounds < 1) {
    throw std::invalid_argument("--seconds must be > 0 and --rounds >= 1");
  }
  return o;
}

constexpr std::chrono::milliseconds kCatchUp{10};
constexpr std::chrono::milliseconds kPosePeriod{500};
constexpr double kPulsesPerRad = 4096 / (2 * std::numbers::pi);
constexpr std::int64_t kCentre = 2048;
// Two poses inside every joint's range (rad, shoulder_pan to gripper).
const std::vector<std::vector<double>> kPoses{{0.5, -0.6, 0.8, 0.4, 1.0, 0.6},
                                              {-0.4, 0.3, -0.2, -0.5, -1.0, 0.1}};

double thread_cpu_s() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + static_cast<double>(t.tv_nsec) * 1e-9;
}

struct Run {
  double wall_s = 0;
  double cpu_s = 0;
};

Run run(const app::BusConfig& config, bool with_physics, double seconds) {
  test::ArmRig rig(config, with_physics);
  for (auto& servo : rig.servos()) {
    rig.set(servo->id(), "goal_position", rig.get(servo->id(), "present_position"));
    rig.set(servo->id(), "torque_switch", 1);
  }
  const auto end = rig.now() + std::chrono::duration_cast<sim::SimDuration>(
                                   std::chrono::duration<double>(seconds));
  std::int64_t sink = 0;  // every read is used, so none is optimised away
  const auto wall0 = std::chrono::steady_clock::now();
  const double cpu0 = thread_cpu_s();
  std::size_t pose = 0;
  auto next_pose = rig.now();
  while (rig.now() < end) {
    if (rig.now() >= next_pose) {
      for (std::size_t i = 0; i < kPoses[pose].size(); ++i) {
        rig.set(static_cast<std::uint8_t>(i + 1), "goal_position",
                kCentre + std::lround(kPoses[pose][i] * kPulsesPerRad));
      }
      pose = 1 - pose;
      next_pose += kPosePeriod;
    }
    rig.wait(kCatchUp);
    for (auto& servo : rig.servos()) {
      sink += rig.get(servo->id(), "present_position") + rig.get(servo->id(), "present_current");
    }
  }
  Run r;
  r.cpu_s = thread_cpu_s() - cpu0;
  r.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  if (sink == 0) {
    std::fprintf(stderr, "(no motion read)\n");
  }
  return r;
}

void body(const Options& o) {
  const std::string robots = DXLEMU_ROBOTS_DIR;
  const app::BusConfig config = test::profile_with_physics(robots + "/so101-follower.json",
                                                           robots + "/physics/so101-follower.json");
  std::vector<double> wall_physics;
  std::vector<double> wall_plain;
  std::vector<double> cpu_physics;
  std::vector<double> cpu_plain;
  std::vector<double> ratio;
  std::vector<double> cpu_ms_physics;
  std::vector<double> cpu_ms_plain;
  std::vector<double> cpu_ratio;
  for (int round = 0; round < o.rounds; ++round) {
    const Run p = run(config, true, o.seconds);
    const Run n = run(config, false, o.seconds);
    wall_physics.push_back(p.wall_s / o.seconds);
    wall_plain.push_back(n.wall_s / o.seconds);
    cpu_physics.push_back(p.cpu_s / p.wall_s);
    cpu_plain.push_back(n.cpu_s / n.wall_s);
    ratio.push_back(p.wall_s / n.wall_s);
    cpu_ms_physics.push_back(p.cpu_s / o.seconds);
    cpu_ms_plain.push_back(n.cpu_s / o.seconds);
    cpu_ratio.push_back(p.cpu_s / n.cpu_s);
    std::fprintf(stderr, "round %d: physics %.3f s, without %.3f s for %.1f simulated s\n",
                 round + 1, p.wall_s, n.wall_s, o.seconds);
  }
  constexpr double kMsPerS = 1000;
  constexpr double kPercent = 100;
  std::printf(
      "SO-101 follower, 6 x STS3215, 1 kHz motion tick, %.1f simulated s, median of %d "
      "rounds\n\n",
      o.seconds, o.rounds);
  std::printf(
      "| variant | wall ms per simulated s | real-time factor | CPU ms per simulated s | "
      "thread CPU / wall |\n");
  std::printf("|---|---|---|---|---|\n");
  const double mp = bench::median(wall_physics);
  const double mn = bench::median(wall_plain);
  std::printf("| with MuJoCo | %.1f | %.0f | %.1f | %.0f %% |\n", mp * kMsPerS, 1 / mp,
              bench::median(cpu_ms_physics) * kMsPerS, bench::median(cpu_physics) * kPercent);
  std::printf("| without physics | %.1f | %.0f | %.1f | %.0f %% |\n", mn * kMsPerS, 1 / mn,
              bench::median(cpu_ms_plain) * kMsPerS, bench::median(cpu_plain) * kPercent);
  std::printf(
      "\nwith / without physics (median of the rounds' ratios): wall time %.2f, CPU time "
      "%.2f\n",
      bench::median(ratio), bench::median(cpu_ratio));
}

}  // namespace

int main(int argc, char** argv) {
  return bench::bench_main("physics_arm", argc, argv, parse, body);
}
