#include "control/api.hpp"

#include <algorithm>
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <utility>

#include "control/clock_commands.hpp"
#include "control/condition_commands.hpp"
#include "control/fault_commands.hpp"
#include "control/hand_commands.hpp"
#include "control/item_commands.hpp"
#include "control/physics_commands.hpp"
#include "control/port_commands.hpp"
#include "control/reply.hpp"
#include "control/request.hpp"
#include "control/scenario.hpp"
#include "control/trace_commands.hpp"

namespace dxlemu::control {
namespace {

// Deeper nesting is refused while parsing: destroying a request and dumping an echoed "id" are
// recursive, and a line of brackets must not exhaust the stack.
constexpr int kMaxDepth = 32;
// A parser message quotes what it read: a runaway string is cut to this many characters.
constexpr std::size_t kMaxParseMessage = 200;

// --- commands ------------------------------------------------------------------------------------

ordered_json shutdown(Target& target, const Args& /*args*/) {
  target.request_shutdown();
  return ordered_json::object();
}

ordered_json help(Target& /*target*/, const Args& /*args*/) {
  return Api::command_names();
}

// --- the command table -----------------------------------------------------------------------

struct Command {
  std::string_view name;
  /// The arguments it takes besides "id" and "cmd"; any other is refused.
  std::vector<std::string_view> fields;
  ordered_json (*run)(Target& target, const Args& args);
};

const std::vector<Command>& commands() {
  static const std::vector<Command> table = {
      {"list", {}, list},
      {"get", {"port", "servo", "item", "address", "size"}, get},
      {"set", {"port", "servo", "item", "address", "size", "value"}, set},
      {"condition.set",
       {"port", "servo", "ambient_temperature", "supply_voltage", "external_load", "blocked"},
       condition_set},
      {"servo.detach", {"port", "servo"}, servo_detach},
      {"servo.attach", {"port", "servo"}, servo_attach},
      {"servo.power_cycle", {"port", "servo"}, servo_power_cycle},
      {"servo.reboot", {"port", "servo"}, servo_reboot},
      {"servo.factory_reset", {"port", "servo", "keep"}, servo_factory_reset},
      {"fault.add", {"rule"}, fault_add},
      {"fault.list", {}, fault_list},
      {"fault.remove", {"rule"}, fault_remove},
      {"fault.clear", {}, fault_clear},
      {"scenario.load", {"file", "scenario"}, scenario_load},
      {"trace.subscribe", {"port"}, trace_subscribe},
      {"trace.unsubscribe", {}, trace_unsubscribe},
      {"hand", {"port"}, hand_state},
      {"hand.play",
       {"port", "file", "loop", "speed", "start_s", "interpolation", "force_limit_nm"},
       hand_play},
      {"hand.sweep",
       {"port", "joints", "order", "speed_deg_s", "to", "force_limit_nm"},
       hand_sweep},
      {"hand.move",
       {"port", "joint", "position", "units", "duration_s", "force_limit_nm"},
       hand_move},
      {"hand.stop", {"port", "joints"}, hand_stop},
      {"physics", {"joint"}, physics_state},
      {"physics.apply", {"joint", "body", "torque_nm", "force_n"}, physics_apply},
      {"clock.now", {}, clock_now},
      {"clock.step", {"ms", "us", "ns"}, clock_step},
      {"stats", {"port"}, stats},
      {"shutdown", {}, shutdown},
      {"help", {}, help},
  };
  return table;
}

const Command& command_for(const ordered_json& request) {
  const auto cmd = request.find("cmd");
  if (cmd == request.end()) {
    refuse("\"cmd\" is required (commands: " + joined(Api::command_names()) + ")");
  }
  if (!cmd->is_string()) {
    refuse("\"cmd\" must be a string");
  }
  const auto& name = cmd->get_ref<const std::string&>();
  const auto& table = commands();
  const auto found = std::find_if(table.begin(), table.end(),
                                  [&](const Command& command) { return command.name == name; });
  if (found == table.end()) {
    refuse("unknown command " + json_quoted(name) + " (commands: " + joined(Api::command_names()) +
           ")");
  }
  return *found;
}

void check_fields(const ordered_json& request, const Command& command) {
  for (const auto& [key, value] : request.items()) {
    if (key == "id" || key == "cmd" ||
        std::find(command.fields.begin(), command.fields.end(), key) != command.fields.end()) {
      continue;
    }
    std::string takes;
    for (const auto field : command.fields) {
      takes += (takes.empty() ? "" : ", ") + std::string(field);
    }
    refuse("unknown field " + json_quoted(key) + " for " + std::string(command.name) +
           " (it takes " + (takes.empty() ? "no arguments" : takes) + ")");
  }
}

ordered_json parse(std::string_view line) {
  const ordered_json::parser_callback_t limit_depth =
      [](int depth, ordered_json::parse_event_t /*event*/, ordered_json& /*parsed*/) {
        if (depth > kMaxDepth) {
          refuse("the request nests deeper than " + std::to_string(kMaxDepth) + " levels");
        }
        return true;
      };
  try {
    return ordered_json::parse(line.begin(), line.end(), limit_depth);
  } catch (const ordered_json::exception& e) {
    // Not only parse_error: a number too large for a double ("1e999") is out_of_range.406.
    // what() is "[json.exception.parse_error.101] parse error at ...": keep from "parse error".
    std::string text = e.what();
    if (const auto start = text.find("] "); start != std::string::npos) {
      text.erase(0, start + 2);
    }
    if (text.size() > kMaxParseMessage) {
      text.resize(kMaxParseMessage);
      text += "...";
    }
    refuse("not valid JSON: " + text);
  }
}

}  // namespace

Api::Api(Target& target) : target_(target) {}

std::vector<std::string> Api::command_names() {
  std::vector<std::string> names;
  for (const Command& command : commands()) {
    names.emplace_back(command.name);
  }
  return names;
}

std::string Api::handle(std::string_view line, const Connection* connection) {
  ordered_json request;
  try {
    request = parse(line);
  } catch (const Refusal& e) {
    return reply_line(error_reply(nullptr, e.what()));
  }
  return reply_line(run(request, connection));
}

ordered_json Api::run(const ordered_json& request, const Connection* connection) {
  ordered_json id = nullptr;
  try {
    if (!request.is_object()) {
      refuse("a request must be a JSON object, e.g. {\"id\":1,\"cmd\":\"list\"}");
    }
    if (const auto given = request.find("id"); given != request.end()) {
      id = *given;
    }
    const Command& command = command_for(request);
    check_fields(request, command);
    ordered_json result = command.run(target_, Args(request, command.name, connection));
    return ok_reply(id, std::move(result));
  } catch (const Refusal& e) {
    return error_reply(std::move(id), e.what());
  } catch (const std::exception& e) {
    // Our own bug (or memory exhaustion): say so rather than drop the connection.
    return error_reply(std::move(id), internal_error(e.what()));
  }
}

std::optional<std::string> Api::check(Target& target, const ordered_json& request) {
  try {
    if (!request.is_object()) {
      refuse("a request must be a JSON object");
    }
    const Command& command = command_for(request);
    check_fields(request, command);
    const Args args(request, command.name);
    if (args.has("servo")) {
      servo_on(port_of(target, args), args.required_integer("servo"));
    } else if (args.has("port")) {
      port_of(target, args);
    }
    if (command.name == "fault.add") {
      rule_of(target, args.value("rule"));
    }
    if (command.name.starts_with("hand.")) {
      check_hand_request(target, args);
    }
    if (command.name == "physics" || command.name == "physics.apply") {
      check_physics_request(target, args);
    }
  } catch (const std::exception& e) {
    return std::string(e.what());
  }
  return std::nullopt;
}

}  // namespace dxlemu::control
