#include "support/daemon.hpp"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "support/serial_port.hpp"

extern char** environ;  // NOLINT(readability-redundant-declaration): posix_spawn needs it

namespace dxlemu::bench {

namespace {

// How long dxlemu may take to print its readiness lines (32 ports of servos take a moment).
constexpr std::chrono::seconds kStartTimeout{30};

}  // namespace

Daemon::Daemon(const std::string& binary, const std::vector<std::string>& args, std::size_t ports)
    : Daemon(
          [&] {
            std::vector<std::string> all = {binary, "run"};
            all.insert(all.end(), args.begin(), args.end());
            return all;
          }(),
          ports) {}

Daemon::Daemon(std::vector<std::string> command, std::size_t ports) {
  if (command.empty()) {
    throw std::invalid_argument("Daemon: no program to start");
  }
  // A bench whose output is piped into `head` would die of SIGPIPE without stopping the daemon
  // it started; ignored, the write fails instead and the destructor still stops it.
  std::signal(SIGPIPE, SIG_IGN);
  const std::string binary = command.front();
  std::array<int, 2> out{};
  if (pipe2(out.data(), O_CLOEXEC) != 0) {
    fail("pipe2");
  }
  posix_spawn_file_actions_t actions{};
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, out[1], STDOUT_FILENO);
  std::vector<char*> argv;
  argv.reserve(command.size() + 1);
  for (std::string& a : command) {
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
    const auto give_up = Clock::now() + kStartTimeout;
    std::string line;
    while (ready_.size() < ports) {
      char c = 0;
      pollfd p{stdout_, POLLIN, 0};
      const auto left = std::chrono::ceil<std::chrono::milliseconds>(give_up - Clock::now());
      if (left.count() <= 0 || poll(&p, 1, static_cast<int>(left.count())) <= 0 ||
          ::read(stdout_, &c, 1) != 1) {
        throw std::runtime_error(binary + " printed no readiness line");
      }
      if (c == '\n') {
        ready_.push_back(nlohmann::json::parse(line));
        line.clear();
      } else {
        line += c;
      }
    }
  } catch (...) {
    stop();
    throw;
  }
}

Daemon::~Daemon() {
  stop();
}

std::string Daemon::pty(std::size_t index) const {
  return ready_.at(index).at("pty").get<std::string>();
}

int Daemon::stop() {
  if (stopped_) {
    return 0;
  }
  stopped_ = true;
  kill(pid_, SIGTERM);
  int status = 0;
  waitpid(pid_, &status, 0);
  ::close(stdout_);
  return status;
}

std::chrono::nanoseconds cpu_time(pid_t pid) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/stat");
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  // The command name may hold spaces: fields count from after its closing parenthesis.
  std::istringstream fields(text.substr(text.rfind(')') + 2));
  std::string field;
  long utime = 0;
  long stime = 0;
  for (int i = 3; i <= 15 && fields >> field; ++i) {
    if (i == 14) {
      utime = std::stol(field);
    } else if (i == 15) {
      stime = std::stol(field);
    }
  }
  const long ticks = sysconf(_SC_CLK_TCK);
  return std::chrono::nanoseconds((utime + stime) * (1'000'000'000L / ticks));
}

long peak_rss_kib(pid_t pid) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/status");
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("VmHWM:", 0) == 0) {
      return std::stol(line.substr(6));
    }
  }
  return -1;
}

std::chrono::nanoseconds run_time(pid_t pid) {
  // A thread that ended since is no longer listed: fine for daemons with one thread (dxlemu).
  std::chrono::nanoseconds total{0};
  for (const auto& task :
       std::filesystem::directory_iterator("/proc/" + std::to_string(pid) + "/task")) {
    std::ifstream in(task.path() / "schedstat");
    long long ns = 0;
    if (in >> ns) {
      total += std::chrono::nanoseconds(ns);
    }
  }
  return total;
}

long proc_status_number(pid_t pid, const std::string& field) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/status");
  const std::string prefix = field + ":";
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind(prefix, 0) == 0) {
      return std::stol(line.substr(prefix.size()));
    }
  }
  return -1;
}

}  // namespace dxlemu::bench
