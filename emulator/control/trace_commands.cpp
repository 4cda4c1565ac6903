#include "control/trace_commands.hpp"

namespace dxlemu::control {

namespace {

const Connection& connection(const Args& args) {
  if (args.connection() == nullptr) {
    refuse(std::string(args.command()) + " needs a connection to send events to");
  }
  return *args.connection();
}

}  // namespace

ordered_json trace_subscribe(Target& target, const Args& args) {
  const Connection& client = connection(args);
  std::vector<std::string> ports;
  if (args.has("port")) {
    ports.push_back(port_of(target, args).name);
  }
  target.subscribe_trace(client, ports);
  return {{"ports", ports.empty() ? target.port_names() : ports}};
}

ordered_json trace_unsubscribe(Target& target, const Args& args) {
  target.unsubscribe_trace(connection(args).id);
  return ordered_json::object();
}

}  // namespace dxlemu::control
