#pragma once

#include <optional>
#include <string>
#include <string_view>

namespace dxlemu::app {

/// How much dxlemu says on stderr (`--log-level`): each level includes the ones before it.
enum class LogLevel { Error, Warn, Info, Debug };

/// The level named "error", "warn", "info" or "debug", or nullopt.
std::optional<LogLevel> parse_log_level(std::string_view name);

/// Sets the level below which messages are dropped (Info unless set).
void set_log_level(LogLevel level);

/// True when a message at `level` would be written (to skip building expensive messages).
bool log_enabled(LogLevel level);

/// Writes "dxlemu: LEVEL: message" to stderr when `level` is enabled.
void log(LogLevel level, std::string_view message);

}  // namespace dxlemu::app
