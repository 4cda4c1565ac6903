#include "app/config/hand_start.hpp"

#include <nlohmann/json.hpp>
#include <stdexcept>
#include <system_error>

namespace dxlemu::app {
namespace {

using nlohmann::ordered_json;

constexpr const char* kSweep = "sweep";

/// `text` as JSON when it parses as a number, true, false or null; else as a string.
ordered_json option_value(const std::string& text) {
  const ordered_json parsed = ordered_json::parse(text, nullptr, false);
  return parsed.is_discarded() || parsed.is_structured() ? ordered_json(text) : parsed;
}

HandStart start_of(const ordered_json& request, const std::string& origin) {
  return HandStart{request.dump(), origin};
}

/// `file` as read from `folder` when a file is there; else as written (a shipped name, or a
/// path relative to where dxlemu runs).
std::string located(const std::string& file, const std::filesystem::path& folder) {
  std::error_code error;
  const std::filesystem::path path(file);
  if (path.is_relative() && std::filesystem::is_regular_file(folder / path, error)) {
    return (folder / path).string();
  }
  return file;
}

}  // namespace

HandStart hand_start_of_option(const std::string& spec) {
  std::vector<std::string> parts;
  std::size_t from = 0;
  while (true) {
    const std::size_t comma = spec.find(',', from);
    parts.push_back(spec.substr(from, comma - from));
    if (comma == std::string::npos) {
      break;
    }
    from = comma + 1;
  }
  if (parts.front().empty()) {
    throw std::invalid_argument(
        "--hand: give a trajectory FILE or \"sweep\", then options: "
        "--hand FILE[,KEY=VALUE]... (docs/hands.md)");
  }
  ordered_json request;
  if (parts.front() == kSweep) {
    request["cmd"] = "hand.sweep";
  } else {
    request["cmd"] = "hand.play";
    request["file"] = parts.front();
  }
  for (std::size_t i = 1; i < parts.size(); ++i) {
    const std::string& part = parts[i];
    const std::size_t equals = part.find('=');
    const std::string key = part.substr(0, equals);
    if (key.empty()) {
      throw std::invalid_argument("--hand " + spec + ": an option without a name (KEY=VALUE)");
    }
    request[key] =
        equals == std::string::npos ? ordered_json(true) : option_value(part.substr(equals + 1));
  }
  return start_of(request, "--hand " + spec);
}

std::vector<HandStart> hand_starts_of_json(const nlohmann::json& value, const std::string& origin,
                                           const std::string& pointer,
                                           const std::filesystem::path& folder) {
  std::vector<HandStart> starts;
  if (value.is_array()) {
    for (std::size_t i = 0; i < value.size(); ++i) {
      for (HandStart& start :
           hand_starts_of_json(value[i], origin, pointer + "/" + std::to_string(i), folder)) {
        starts.push_back(std::move(start));
      }
    }
    return starts;
  }
  const std::string where = origin + ": " + pointer;
  if (value.is_string()) {
    HandStart start = hand_start_of_option(value.get<std::string>());
    ordered_json request = ordered_json::parse(start.request);
    if (request.contains("file")) {
      request["file"] = located(request["file"].get<std::string>(), folder);
    }
    starts.push_back(start_of(request, where));
    return starts;
  }
  if (!value.is_object()) {
    throw ConfigError(origin, pointer,
                      "must be a trajectory FILE, \"sweep\", an object with \"file\" or "
                      "\"sweep\", or an array of these (docs/hands.md)");
  }
  const bool file = value.contains("file");
  const bool sweep = value.contains(kSweep);
  if (file == sweep) {
    throw ConfigError(origin, pointer, "needs one of \"file\" (a trajectory) or \"sweep\": true");
  }
  ordered_json request;
  request["cmd"] = sweep ? "hand.sweep" : "hand.play";
  for (const auto& [key, member] : value.items()) {
    if (key == kSweep) {
      if (member != true) {
        throw ConfigError(origin, pointer + "/sweep", "must be true");
      }
      continue;
    }
    if (key == "file") {
      if (!member.is_string()) {
        throw ConfigError(origin, pointer + "/file", "must be a trajectory file or name");
      }
      request["file"] = located(member.get<std::string>(), folder);
      continue;
    }
    request[key] = ordered_json::parse(member.dump());
  }
  starts.push_back(start_of(request, where));
  return starts;
}

}  // namespace dxlemu::app
