#include "io/child_process.hpp"

#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <cstring>
#include <iostream>
#include <system_error>

namespace dxlemu::io {
namespace {

constexpr std::array<int, 4> kPassedOn = {SIGTERM, SIGHUP, SIGINT, SIGQUIT};

volatile sig_atomic_t child_pid = 0;

// Only a signal sent by a process (si_code SI_USER, SI_QUEUE, SI_TKILL: all <= 0) is passed on;
// one from the kernel, such as a terminal's ^C, already reached the child's process group.
void pass_on(int signal, siginfo_t* info, void* /*context*/) {
  if (info != nullptr && info->si_code <= 0 && child_pid > 0) {
    ::kill(child_pid, signal);
  }
}

// This process's environment with `changes` applied, as "NAME=value" strings.
std::vector<std::string> environment_with(const std::map<std::string, std::string>& changes) {
  std::vector<std::string> out;
  for (char** entry = environ; *entry != nullptr; ++entry) {
    const std::string text = *entry;
    if (!changes.contains(text.substr(0, text.find('=')))) {
      out.push_back(text);
    }
  }
  for (const auto& [name, value] : changes) {
    out.push_back(name + "=" + value);
  }
  return out;
}

std::vector<char*> pointers(std::vector<std::string>& strings) {
  std::vector<char*> out;
  out.reserve(strings.size() + 1);
  for (std::string& s : strings) {
    out.push_back(s.data());
  }
  out.push_back(nullptr);
  return out;
}

// The signals passed on to the child, as a set.
sigset_t passed_on() {
  sigset_t set;
  sigemptyset(&set);
  for (const int signal : kPassedOn) {
    sigaddset(&set, signal);
  }
  return set;
}

// Spawns with the passed-on signals at their defaults in the child and `mask` as its signal
// mask, whatever this process does with them meanwhile.
int spawn(pid_t& pid, std::vector<std::string> arguments, std::vector<std::string> environment,
          const sigset_t& mask) {
  posix_spawnattr_t attributes;
  posix_spawnattr_init(&attributes);
  const sigset_t defaults = passed_on();
  posix_spawnattr_setsigdefault(&attributes, &defaults);
  posix_spawnattr_setsigmask(&attributes, &mask);
  posix_spawnattr_setflags(&attributes, POSIX_SPAWN_SETSIGDEF | POSIX_SPAWN_SETSIGMASK);
  auto argv = pointers(arguments);
  auto envp = pointers(environment);
  const int error = ::posix_spawnp(&pid, argv[0], nullptr, &attributes, argv.data(), envp.data());
  posix_spawnattr_destroy(&attributes);
  return error;
}

}  // namespace

int run_child(const std::vector<std::string>& command,
              const std::map<std::string, std::string>& environment) {
  struct sigaction action {};
  action.sa_sigaction = pass_on;
  action.sa_flags = SA_SIGINFO | SA_RESTART;
  sigemptyset(&action.sa_mask);
  // Installed, and blocked, before the spawn: the child may run (and be seen running) before
  // child_pid is set, and a signal sent then must wait for child_pid rather than be dropped. The
  // child starts with the mask this process had.
  const sigset_t blocked = passed_on();
  sigset_t mask;
  ::sigprocmask(SIG_BLOCK, &blocked, &mask);
  for (const int signal : kPassedOn) {
    ::sigaction(signal, &action, nullptr);
  }
  pid_t pid = 0;
  const int error = spawn(pid, command, environment_with(environment), mask);
  if (error == 0) {
    child_pid = pid;
  }
  ::sigprocmask(SIG_SETMASK, &mask, nullptr);
  if (error != 0) {
    std::cerr << "dxlemu exec: cannot run " << command.front() << ": " << std::strerror(error)
              << "\n";
    return error == ENOENT ? kExitNotFound : kExitCannotExecute;
  }
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0) {
    if (errno != EINTR) {
      throw std::system_error(errno, std::generic_category(), "waiting for " + command.front());
    }
  }
  child_pid = 0;
  if (WIFSIGNALED(status)) {
    return kExitSignalBase + WTERMSIG(status);
  }
  return WEXITSTATUS(status);
}

}  // namespace dxlemu::io
