#include "app/daemon/log.hpp"

#include <array>
#include <iostream>

namespace dxlemu::app {
namespace {

constexpr std::array<const char*, 4> kNames = {"error", "warn", "info", "debug"};

// One thread runs the emulator (DESIGN.md), so a plain variable is enough.
LogLevel g_level = LogLevel::Info;

}  // namespace

std::optional<LogLevel> parse_log_level(std::string_view name) {
  for (std::size_t i = 0; i < kNames.size(); ++i) {
    if (name == kNames[i]) {
      return static_cast<LogLevel>(i);
    }
  }
  return std::nullopt;
}

void set_log_level(LogLevel level) {
  g_level = level;
}

bool log_enabled(LogLevel level) {
  return level <= g_level;
}

void log(LogLevel level, std::string_view message) {
  if (log_enabled(level)) {
    std::cerr << "dxlemu: " << kNames[static_cast<std::size_t>(level)] << ": " << message
              << std::endl;
  }
}

}  // namespace dxlemu::app
