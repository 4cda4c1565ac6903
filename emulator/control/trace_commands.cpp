#include "control/trace_commands.hpp"

namespace dxlemu::control {

namespace {

std::uint64_t connection(const Args& args) {
  if (args.client() == 0) {
    refuse(std::string(args.command()) + " needs a connection to send events to");
  }
  return args.client();
}

}  // namespace

ordered_json trace_subscribe(Target& target, const Args& args) {
  const std::uint64_t client = connection(args);
  std::vector<std::string> ports;
  if (args.has("port")) {
    ports.push_back(port_of(target, args).name);
  }
  target.subscribe_trace(client, ports);
  return {{"ports", ports.empty() ? target.port_names() : ports}};
}

ordered_json trace_unsubscribe(Target& target, const Args& args) {
  target.unsubscribe_trace(connection(args));
  return ordered_json::object();
}

}  // namespace dxlemu::control
