#pragma once

#include <functional>
#include <map>
#include <string>

namespace dxlemu::bench {

/// What to do with the value of each `--name value` flag, by name ("--count").
using FlagHandlers = std::map<std::string, std::function<void(const std::string& value)>>;

/// Hands every `--name value` pair of argv to its handler, in order. An unknown flag, a flag
/// without a value, or a value its handler refuses (std::stoi and friends throw
/// std::logic_error) throws std::invalid_argument(usage).
void parse_flags(int argc, char** argv, const FlagHandlers& handlers, const std::string& usage);

}  // namespace dxlemu::bench
