// Timing fidelity of the real-time driver (issue 5's target, the first benchmark of issue 8): how
// far from its modelled time a reply reaches a client on the PTY.
//
// For each baud rate the bench starts `dxlemu run` with one XM430-W350 (ID 1, factory settings
// but the baud), reads the readiness line to learn the PTY, and sends N Pings and N Reads of
// Present Position (4 bytes), one at a time, as a controller does. For every round trip:
//
//   lateness = (steady_clock when the read() that completed the status returned)
//            - (steady_clock when the write() of the instruction returned
//               + wire(instruction) + processing time + Return Delay Time + wire(status))
//
// which is the reply timing of docs/bus.md measured from outside. Both processes read the same
// CLOCK_MONOTONIC. The result is a Markdown table on stdout (scripts/bench.sh puts it in
// docs/benchmarks.md); progress goes to stderr.
//
// Usage: reply_latency --dxlemu PATH [--baud BPS]... [--count N] [--warmup N] [--cpu N]
//        reply_latency --pty PATH --baud BPS [--count N] [--warmup N] [--cpu N]
// The second form measures an emulator already serving one xm430-w350 with ID 1 at BPS on PATH.
// The client waits in poll(2), as a blocking serial client does. --cpu N pins the bench, and the
// dxlemu it starts, to CPU N: the reply then wakes the client on the CPU that sent it, which
// takes the cost of waking another (idle, possibly halted virtual) CPU out of the figures.
//
// The client's baud is set with TCSETS2/BOTHER, so any rate works; that needs <asm/termbits.h>,
// which clashes with <termios.h>, so this file includes only the kernel's header.
#include <asm/termbits.h>
#include <fcntl.h>
#include <poll.h>
#include <sched.h>
#include <signal.h>
#include <spawn.h>
#include <sys/ioctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <system_error>
#include <vector>

#include "bus/line_timing.hpp"
#include "wire/crc16.hpp"
#include "wire/instruction_encoder.hpp"
#include "wire/protocol.hpp"

extern char** environ;  // NOLINT(readability-redundant-declaration): posix_spawn needs it

namespace {

using Clock = std::chrono::steady_clock;
using std::chrono::microseconds;
using std::chrono::milliseconds;
using std::chrono::nanoseconds;

constexpr std::uint8_t kServoId = 1;
constexpr const char* kServo = "xm430-w350:1";
// models/xm430-w350.json "timing": ping_us and read_us are both 50.
constexpr microseconds kProcessing{50};
// Factory Return Delay Time of the XM430-W350: item value 250 × 2 µs (control table address 9).
constexpr microseconds kReturnDelay{500};
// Present Position (address 132, 4 bytes) of the X series control table.
constexpr std::uint16_t kPresentPosition = 132;
constexpr std::uint16_t kPresentPositionSize = 4;
// A 2.0 status packet: header (4), ID, LENGTH (2), instruction 0x55, error, parameters, CRC (2).
constexpr std::size_t kStatusOverhead = 11;
constexpr std::size_t kPingStatusParams = 3;  // model number (2), firmware version
constexpr std::size_t kStatusIdIndex = 4;
constexpr std::size_t kStatusInstructionIndex = 7;
constexpr std::size_t kStatusErrorIndex = 8;
constexpr auto kStatusInstruction =
    static_cast<std::uint8_t>(dxlemu::wire::InstructionCode::Status);
constexpr std::uint8_t kByteBits = 8;
constexpr std::uint8_t kByteMask = 0xFF;

// How long to wait for a reply before counting it lost, beyond its modelled time.
constexpr milliseconds kReplyTimeout{100};
// How long dxlemu may take to print its readiness line.
constexpr milliseconds kStartTimeout{10'000};
// After a lost or bad reply, let stray bytes arrive before discarding them.
constexpr milliseconds kSettle{20};
// A write() of a dozen bytes to a PTY takes a few µs. When it takes longer, the client was
// preempted inside it, the moment the bytes reached the emulator is unknown (the reply may even
// arrive before write() returns), and the round trip is skipped and counted, not measured.
constexpr microseconds kMaxWriteTime{100};

constexpr double kMedian = 0.5;
constexpr double kP99 = 0.99;
constexpr double kNanosPerMicro = 1000.0;

struct Options {
  std::string dxlemu;
  std::string pty;
  std::vector<std::uint32_t> bauds;
  int count = 2000;
  int warmup = 50;
  int cpu = -1;  // with --cpu N, the bench and the dxlemu it starts run on CPU N only
};

// One kind of round trip: the instruction's bytes and the status length it expects.
struct Case {
  std::string name;
  std::vector<std::uint8_t> instruction;
  std::size_t status_size = 0;
};

struct Result {
  std::vector<nanoseconds> lateness;  // one per round trip after the warm-up
  int lost = 0;                       // no reply within the timeout, or not the expected one
  int skipped = 0;                    // write() took longer than kMaxWriteTime
  nanoseconds modelled{0};            // modelled round trip (write returned -> last byte)
};

[[noreturn]] void fail(const std::string& what) {
  throw std::system_error(errno, std::generic_category(), what);
}

// The dxlemu daemon as a child process; SIGTERM and wait when destroyed.
class Daemon {
 public:
  Daemon(const std::string& binary, std::uint32_t bps) {
    std::array<int, 2> out{};
    if (pipe2(out.data(), O_CLOEXEC) != 0) {
      fail("pipe2");
    }
    posix_spawn_file_actions_t actions{};
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_adddup2(&actions, out[1], STDOUT_FILENO);
    link_ = "/tmp/dxlemu-bench-" + std::to_string(getpid());
    std::vector<std::string> args = {
        binary, "run", "--servo", kServo, "--baud", std::to_string(bps), "--link", link_};
    std::vector<char*> argv;
    argv.reserve(args.size() + 1);
    for (std::string& a : args) {
      argv.push_back(a.data());
    }
    argv.push_back(nullptr);
    const int err = posix_spawn(&pid_, binary.c_str(), &actions, nullptr, argv.data(), environ);
    posix_spawn_file_actions_destroy(&actions);
    ::close(out[1]);
    stdout_ = out[0];
    if (err != 0) {
      errno = err;
      fail("starting " + binary);
    }
    try {
      pty_ = read_ready_line();
    } catch (...) {
      stop();
      throw;
    }
  }
  ~Daemon() { stop(); }
  Daemon(const Daemon&) = delete;
  Daemon& operator=(const Daemon&) = delete;

  const std::string& pty() const { return pty_; }

 private:
  // The "pty" of the readiness line (README "Running the emulator").
  std::string read_ready_line() const {
    std::string line;
    const auto give_up = Clock::now() + kStartTimeout;
    char c = 0;
    while (c != '\n') {
      pollfd p{stdout_, POLLIN, 0};
      const auto left = std::chrono::duration_cast<milliseconds>(give_up - Clock::now());
      if (left.count() <= 0 || poll(&p, 1, static_cast<int>(left.count())) <= 0 ||
          ::read(stdout_, &c, 1) != 1) {
        throw std::runtime_error("dxlemu printed no readiness line");
      }
      line += c;
    }
    return nlohmann::json::parse(line).at("pty").get<std::string>();
  }

  void stop() const {
    kill(pid_, SIGTERM);
    int status = 0;
    waitpid(pid_, &status, 0);
    ::close(stdout_);
  }

  pid_t pid_ = 0;
  int stdout_ = -1;
  std::string link_;
  std::string pty_;
};

// Opens the client side of the port raw at `bps` (8N1, no flow control).
int open_port(const std::string& path, std::uint32_t bps) {
  const int fd = ::open(path.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) {
    fail("opening " + path);
  }
  termios2 t{};
  if (ioctl(fd, TCGETS2, &t) != 0) {
    fail("TCGETS2");
  }
  // What cfmakeraw does, with the kernel's struct.
  t.c_iflag &= ~(IGNBRK | BRKINT | PARMRK | ISTRIP | INLCR | IGNCR | ICRNL | IXON);
  t.c_oflag &= ~OPOST;
  t.c_lflag &= ~(ECHO | ECHONL | ICANON | ISIG | IEXTEN);
  t.c_cflag &= ~(CSIZE | PARENB | CBAUD | CRTSCTS);
  t.c_cflag |= CS8 | CREAD | CLOCAL | BOTHER;
  t.c_ispeed = bps;
  t.c_ospeed = bps;
  if (ioctl(fd, TCSETS2, &t) != 0) {
    fail("TCSETS2");
  }
  ioctl(fd, TCFLSH, TCIOFLUSH);
  return fd;
}

// Restricts this process, and the processes it starts later, to one CPU.
void pin_to_cpu(int cpu) {
  cpu_set_t set;
  CPU_ZERO(&set);
  CPU_SET(cpu, &set);
  if (sched_setaffinity(0, sizeof(set), &set) != 0) {
    fail("pinning to CPU " + std::to_string(cpu));
  }
}

bool valid_status(std::span<const std::uint8_t> s) {
  const std::uint16_t crc = dxlemu::wire::crc16(s.first(s.size() - 2));
  const auto low = static_cast<std::uint8_t>(crc & kByteMask);
  const auto high = static_cast<std::uint8_t>(crc >> kByteBits);
  return s[0] == kByteMask && s[1] == kByteMask && s[kStatusIdIndex] == kServoId &&
         s[kStatusInstructionIndex] == kStatusInstruction && s[kStatusErrorIndex] == 0 &&
         s[s.size() - 2] == low && s[s.size() - 1] == high;
}

// Reads exactly `out.size()` bytes; the time the last read() returned, or nothing on timeout.
std::optional<Clock::time_point> read_exactly(int fd, std::span<std::uint8_t> out,
                                              Clock::time_point give_up) {
  std::size_t got = 0;
  while (got < out.size()) {
    const auto left = std::chrono::ceil<milliseconds>(give_up - Clock::now());
    pollfd p{fd, POLLIN, 0};
    if (left.count() <= 0 || poll(&p, 1, static_cast<int>(left.count())) <= 0) {
      return std::nullopt;
    }
    const ssize_t n = ::read(fd, out.data() + got, out.size() - got);
    if (n < 0 && errno != EINTR && errno != EAGAIN) {
      fail("read");
    }
    got += n > 0 ? static_cast<std::size_t>(n) : 0;
  }
  return Clock::now();
}

Result measure(int fd, std::uint32_t bps, const Case& c, const Options& options) {
  Result r;
  r.modelled = dxlemu::bus::wire_time(c.instruction.size(), bps) + kProcessing + kReturnDelay +
               dxlemu::bus::wire_time(c.status_size, bps);
  r.lateness.reserve(static_cast<std::size_t>(options.count));
  std::vector<std::uint8_t> status(c.status_size);
  for (int i = 0; i < options.warmup + options.count; ++i) {
    const bool counted = i >= options.warmup;
    const Clock::time_point before = Clock::now();
    if (::write(fd, c.instruction.data(), c.instruction.size()) !=
        static_cast<ssize_t>(c.instruction.size())) {
      fail("write");
    }
    const Clock::time_point sent = Clock::now();
    const auto got = read_exactly(fd, status, sent + r.modelled + kReplyTimeout);
    if (!got || !valid_status(status)) {
      r.lost += counted ? 1 : 0;
      usleep(std::chrono::duration_cast<microseconds>(kSettle).count());
      ioctl(fd, TCFLSH, TCIFLUSH);
    } else if (sent - before > kMaxWriteTime) {
      r.skipped += counted ? 1 : 0;
    } else if (counted) {
      r.lateness.push_back(*got - (sent + r.modelled));
    }
  }
  return r;
}

std::string us(nanoseconds d) {
  std::array<char, 32> text{};
  std::snprintf(text.data(), text.size(), "%.1f", static_cast<double>(d.count()) / kNanosPerMicro);
  return text.data();
}

void print_row(std::uint32_t bps, const Case& c, Result r) {
  std::sort(r.lateness.begin(), r.lateness.end());
  std::cout << "| " << bps << " | " << c.name << " | " << r.lateness.size() << " | " << r.lost
            << " | " << r.skipped << " | " << us(r.modelled) << " | ";
  if (r.lateness.empty()) {
    std::cout << "- | - | - | - |" << std::endl;
    return;
  }
  const auto n = static_cast<double>(r.lateness.size());
  // Nearest-rank percentiles: the smallest sample with at least p of the samples at or below it.
  const auto rank = [&](double p) {
    return r.lateness[std::max<std::size_t>(1, static_cast<std::size_t>(std::ceil(p * n))) - 1];
  };
  std::cout << us(r.lateness.front()) << " | " << us(rank(kMedian)) << " | " << us(rank(kP99))
            << " | " << us(r.lateness.back()) << " |" << std::endl;
}

std::vector<Case> cases() {
  using dxlemu::wire::InstructionPacket;
  using dxlemu::wire::Protocol;
  return {
      {"Ping", dxlemu::wire::encode_instruction({Protocol::V2, kServoId, dxlemu::wire::Ping{}}),
       kStatusOverhead + kPingStatusParams},
      {"Read 4 B",
       dxlemu::wire::encode_instruction(
           {Protocol::V2, kServoId, dxlemu::wire::Read{kPresentPosition, kPresentPositionSize}}),
       kStatusOverhead + kPresentPositionSize},
  };
}

constexpr const char* kUsage =
    "usage: reply_latency --dxlemu PATH [--baud BPS]... [--count N] [--warmup N] [--cpu N]\n"
    "       reply_latency --pty PATH --baud BPS [--count N] [--warmup N] [--cpu N]";

Options parse(int argc, char** argv) {
  Options o;
  const std::vector<std::string> args(argv + 1, argv + argc);
  try {
    for (std::size_t i = 0; i + 1 < args.size(); i += 2) {
      const std::string& a = args[i];
      const std::string& v = args[i + 1];
      if (a == "--dxlemu") {
        o.dxlemu = v;
      } else if (a == "--pty") {
        o.pty = v;
      } else if (a == "--baud") {
        o.bauds.push_back(static_cast<std::uint32_t>(std::stoul(v)));
      } else if (a == "--count") {
        o.count = std::stoi(v);
      } else if (a == "--warmup") {
        o.warmup = std::stoi(v);
      } else if (a == "--cpu") {
        o.cpu = std::stoi(v);
      } else {
        throw std::invalid_argument(a);
      }
    }
  } catch (const std::logic_error&) {  // an unknown option, or stoi/stoul refusing a number
    throw std::invalid_argument(kUsage);
  }
  if (args.size() % 2 != 0 || o.dxlemu.empty() == o.pty.empty() ||
      (!o.pty.empty() && o.bauds.size() != 1) || o.count <= 0 || o.warmup < 0) {
    throw std::invalid_argument(kUsage);
  }
  if (o.bauds.empty()) {
    o.bauds = {57'600, 1'000'000, 4'000'000};
  }
  return o;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    const Options options = parse(argc, argv);
    if (options.cpu >= 0) {
      pin_to_cpu(options.cpu);  // before starting dxlemu, which inherits it
    }
    std::cout << "| baud | instruction | round trips | lost | skipped | modelled "
                 "(µs) | min (µs) | "
                 "median (µs) "
                 "| p99 (µs) | max (µs) |\n"
                 "|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|"
              << std::endl;
    for (const std::uint32_t bps : options.bauds) {
      std::optional<Daemon> daemon;
      if (!options.dxlemu.empty()) {
        daemon.emplace(options.dxlemu, bps);
      }
      const int fd = open_port(daemon ? daemon->pty() : options.pty, bps);
      for (const Case& c : cases()) {
        std::cerr << "reply_latency: " << c.name << " at " << bps << " bit/s\n";
        print_row(bps, c, measure(fd, bps, c, options));
      }
      ::close(fd);
    }
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "reply_latency: " << e.what() << "\n";
    return 1;
  }
}
