#include "control/reply.hpp"

#include <utility>

#include "control/request.hpp"

namespace dxlemu::control {

using nlohmann::ordered_json;

ordered_json ok_reply(ordered_json id, ordered_json result) {
  return {{"id", std::move(id)}, {"ok", true}, {"result", std::move(result)}};
}

ordered_json error_reply(ordered_json id, std::string_view message) {
  return {{"id", std::move(id)}, {"ok", false}, {"error", std::string(message)}};
}

std::string internal_error(std::string_view what) {
  return "internal error: " + std::string(what);
}

std::string reply_line(const ordered_json& reply) {
  return dumped(reply);
}

std::string oversize_line(std::size_t limit) {
  return reply_line(
      error_reply(nullptr, "request longer than " + std::to_string(limit) + " bytes: discarded"));
}

std::string internal_error_line(std::string_view what) {
  return reply_line(error_reply(nullptr, internal_error(what)));
}

}  // namespace dxlemu::control
