#include "app/cli/ctl_request.hpp"

#include <stdexcept>

namespace dxlemu::app {
namespace {

using nlohmann::json;
using nlohmann::ordered_json;

// ctl sends one request per connection, so any id would do; 1 reads well in error reports.
constexpr int kRequestId = 1;
// Indentation of the printed result.
constexpr int kIndent = 2;
constexpr int kExitRefused = 1;

// Adds `key` to `request`, refusing keys ctl sets itself and keys given twice.
void add_member(ordered_json& request, const std::string& key, ordered_json value,
                const std::string& arg) {
  if (key.empty()) {
    throw std::invalid_argument("argument \"" + arg + "\": the key before '=' is empty");
  }
  if (key == "id" || key == "cmd") {
    throw std::invalid_argument("argument \"" + arg + "\": \"" + key +
                                "\" is set by dxlemu ctl (the command is the first argument)");
  }
  if (request.contains(key)) {
    throw std::invalid_argument("argument \"" + arg + "\": \"" + key + "\" is given twice");
  }
  request[key] = std::move(value);
}

}  // namespace

ordered_json ctl_request(std::string_view command, const std::vector<std::string>& args) {
  if (command.empty()) {
    throw std::invalid_argument("the command is empty (dxlemu ctl help lists the commands)");
  }
  ordered_json request = {{"id", kRequestId}, {"cmd", std::string(command)}};
  for (const std::string& arg : args) {
    // A whole JSON object is merged; anything else must be key=value.
    const auto first = arg.find_first_not_of(" \t");
    if (first != std::string::npos && arg[first] == '{') {
      const ordered_json object = ordered_json::parse(arg, nullptr, false);
      if (object.is_object()) {
        for (const auto& [key, value] : object.items()) {
          add_member(request, key, value, arg);
        }
        continue;
      }
    }
    const auto equals = arg.find('=');
    if (equals == std::string::npos) {
      throw std::invalid_argument("argument \"" + arg + "\": expected key=value or a JSON object");
    }
    const std::string text = arg.substr(equals + 1);
    ordered_json value = ordered_json::parse(text, nullptr, false);
    if (value.is_discarded()) {
      value = text;  // not JSON: a string, so that item=goal_position needs no quotes
    }
    add_member(request, arg.substr(0, equals), std::move(value), arg);
  }
  return request;
}

CtlOutcome ctl_outcome(std::string_view reply_line) {
  const ordered_json reply = ordered_json::parse(reply_line, nullptr, false);
  if (!reply.is_object() || !reply.contains("ok") || !reply["ok"].is_boolean()) {
    return {kExitRefused, "",
            "dxlemu ctl: the daemon's reply is not a control API reply: " +
                std::string(reply_line) + "\n"};
  }
  if (reply["ok"].get<bool>()) {
    return {0, reply.value("result", ordered_json::object()).dump(kIndent) + "\n", ""};
  }
  const ordered_json error = reply.value("error", ordered_json("(no error message)"));
  return {kExitRefused, "",
          "dxlemu ctl: " + (error.is_string() ? error.get<std::string>() : error.dump()) + "\n"};
}

std::filesystem::path ctl_control_socket(const std::optional<std::filesystem::path>& option,
                                         const char* env, const std::filesystem::path& dir,
                                         const LiveSocketFinder& find) {
  if (option) {
    return *option;
  }
  if (env != nullptr && *env != '\0') {
    return env;
  }
  const std::vector<std::filesystem::path> live = find(dir);
  if (live.size() == 1) {
    return live.front();
  }
  const std::string pattern = (dir / "dxlemu-*.sock").string();
  if (live.empty()) {
    throw std::invalid_argument("no running dxlemu found: no live control socket " + pattern +
                                "; pass --control PATH (or set DXLEMU_CONTROL)");
  }
  std::string names;
  for (const auto& path : live) {
    names += (names.empty() ? "" : ", ") + path.string();
  }
  throw std::invalid_argument("several running dxlemu found (" + names +
                              "); pass --control PATH (or set DXLEMU_CONTROL) to choose one");
}

}  // namespace dxlemu::app
