#include "support/daemon.hpp"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
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

Daemon::Daemon(const std::string& binary, const std::vector<std::string>& args, std::size_t ports) {
  std::array<int, 2> out{};
  if (pipe2(out.data(), O_CLOEXEC) != 0) {
    fail("pipe2");
  }
  posix_spawn_file_actions_t actions{};
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, out[1], STDOUT_FILENO);
  std::vector<std::string> all = {binary, "run"};
  all.insert(all.end(), args.begin(), args.end());
  std::vector<char*> argv;
  argv.reserve(all.size() + 1);
  for (std::string& a : all) {
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
        throw std::runtime_error("dxlemu printed no readiness line");
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

}  // namespace dxlemu::bench
