#include "control/request.hpp"

namespace dxlemu::control {

[[noreturn]] void refuse(const std::string& text) {
  throw Refusal(text);
}

std::string dumped(const ordered_json& value) {
  return value.dump(-1, ' ', false, ordered_json::error_handler_t::replace);
}

std::string json_quoted(std::string_view text) {
  return dumped(ordered_json(std::string(text)));
}

std::string joined(const std::vector<std::string>& names) {
  std::string out;
  for (const auto& name : names) {
    out += (out.empty() ? "" : ", ") + name;
  }
  return out;
}

std::string byte_count(std::size_t size) {
  return std::to_string(size) + (size == 1 ? " byte" : " bytes");
}

// --- addressing --------------------------------------------------------------------------------

Port port_of(Target& target, const Args& args) {
  const auto names = target.port_names();
  std::string name;
  if (auto given = args.string("port")) {
    name = std::move(*given);
  } else if (names.size() == 1) {
    name = names.front();
  } else if (names.empty()) {
    refuse("there are no ports");
  } else {
    refuse("\"port\" is required: there are " + std::to_string(names.size()) + " ports (" +
           joined(names) + ")");
  }
  PortView* view = target.port(name);
  if (view == nullptr) {
    refuse("port " + json_quoted(name) + " does not exist (ports: " + joined(names) + ")");
  }
  return {name, *view};
}

model::Servo& servo_on(const Port& port, std::int64_t id) {
  std::vector<model::Servo*> found;
  std::vector<std::string> ids;
  for (model::Servo* servo : port.view.servos()) {
    ids.push_back(std::to_string(servo->id()));
    if (servo->id() == id) {
      found.push_back(servo);
    }
  }
  if (found.empty()) {
    refuse("no servo " + std::to_string(id) + " on " + port.name +
           " (servos: " + (ids.empty() ? "none" : joined(ids)) + ")");
  }
  if (found.size() > 1) {
    refuse(std::to_string(found.size()) + " servos on " + port.name + " have ID " +
           std::to_string(id) + ": the control API cannot tell them apart");
  }
  return *found.front();
}

model::Servo& addressed(Target& target, const Args& args) {
  const Port port = port_of(target, args);
  const std::int64_t id = args.required_integer("servo");
  port.view.catch_up();
  return servo_on(port, id);
}

}  // namespace dxlemu::control
