#pragma once

#include <cstddef>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>

// The one place that knows what a control reply looks like (docs/control-api.md): the API's
// replies, and those the daemon and the socket server send for lines no command ran on.
namespace dxlemu::control {

/// {"id": id, "ok": true, "result": result}: a command done. `id` is the request's, as given.
nlohmann::ordered_json ok_reply(nlohmann::ordered_json id, nlohmann::ordered_json result);

/// {"id": id, "ok": false, "error": message}: a request refused (`id` null when the request had
/// none or could not be read).
nlohmann::ordered_json error_reply(nlohmann::ordered_json id, std::string_view message);

/// The error text when our own code failed rather than the request: "internal error: <what>".
std::string internal_error(std::string_view what);

/// A reply as one line of JSON without the newline; bytes that are not UTF-8 are replaced, so
/// it never throws on what a request echoed.
std::string reply_line(const nlohmann::ordered_json& reply);

/// The reply line to a request line longer than `limit` bytes, which is discarded unread.
std::string oversize_line(std::size_t limit);

/// The reply line when handling a line failed in our own code with `what`.
std::string internal_error_line(std::string_view what);

}  // namespace dxlemu::control
