#pragma once

#include <cstdint>
#include <limits>
#include <nlohmann/json.hpp>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "control/connection.hpp"
#include "control/port_view.hpp"
#include "control/target.hpp"
#include "model/servo.hpp"

// What every control command needs to read its request: refusals, typed arguments, and the port
// and servo a request addresses. Internal to control/.
namespace dxlemu::control {

using nlohmann::ordered_json;

/// A request the API refuses; what() is the error text of the reply.
class Refusal : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Throws Refusal(text).
[[noreturn]] void refuse(const std::string& text);

/// Text for the reply: never throws on bytes that are not UTF-8.
std::string dumped(const ordered_json& value);

/// `text` as a JSON string, quotes included: `"dxl9"`.
std::string json_quoted(std::string_view text);

/// `names` separated by commas.
std::string joined(const std::vector<std::string>& names);

/// "1 byte", "4 bytes".
std::string byte_count(std::size_t size);

/// The arguments of one request, read with the type each command expects: a missing argument is
/// nullopt, one of the wrong type is refused naming it.
class Args {
 public:
  /// The arguments of `request` for `command`, sent by `connection` (null: none, e.g. a scenario
  /// step), which must outlive the Args.
  Args(const ordered_json& request, std::string_view command,
       const Connection* connection = nullptr)
      : request_(request), command_(command), connection_(connection) {}

  std::string_view command() const { return command_; }
  /// The connection that sent the request, or nullptr.
  const Connection* connection() const { return connection_; }

  bool has(std::string_view key) const { return find(key) != nullptr; }

  std::optional<std::int64_t> integer(std::string_view key) const {
    const ordered_json* value = find(key);
    if (value == nullptr) {
      return std::nullopt;
    }
    if (value->is_number_unsigned() &&
        value->get<std::uint64_t>() >
            static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max())) {
      refuse(json_quoted(key) + " is too large");
    }
    if (!value->is_number_integer()) {
      refuse(json_quoted(key) + " must be an integer");
    }
    return value->get<std::int64_t>();
  }

  std::int64_t required_integer(std::string_view key) const {
    const auto value = integer(key);
    if (!value) {
      refuse(json_quoted(key) + " is required");
    }
    return *value;
  }

  std::optional<double> number(std::string_view key) const {
    const ordered_json* value = find(key);
    if (value == nullptr) {
      return std::nullopt;
    }
    if (!value->is_number()) {
      refuse(json_quoted(key) + " must be a number");
    }
    return value->get<double>();
  }

  std::optional<bool> boolean(std::string_view key) const {
    const ordered_json* value = find(key);
    if (value == nullptr) {
      return std::nullopt;
    }
    if (!value->is_boolean()) {
      refuse(json_quoted(key) + " must be true or false");
    }
    return value->get<bool>();
  }

  /// The argument as the request wrote it, or nullptr when it is missing.
  const ordered_json* value(std::string_view key) const { return find(key); }

  /// The argument as the request wrote it (JSON), for messages.
  std::string text(std::string_view key) const {
    const ordered_json* value = find(key);
    return value == nullptr ? "nothing" : dumped(*value);
  }

  std::optional<std::string> string(std::string_view key) const {
    const ordered_json* value = find(key);
    if (value == nullptr) {
      return std::nullopt;
    }
    if (!value->is_string()) {
      refuse(json_quoted(key) + " must be a string");
    }
    return value->get<std::string>();
  }

 private:
  const ordered_json* find(std::string_view key) const {
    const auto it = request_.find(std::string(key));
    return it == request_.end() ? nullptr : &*it;
  }

  const ordered_json& request_;
  std::string_view command_;
  const Connection* connection_;
};

/// A port a request names.
struct Port {
  std::string name;
  PortView& view;
};

/// The port named by "port", or the only port when there is just one.
Port port_of(Target& target, const Args& args);

/// The one servo with `id` on `port`; refused when there is none or several.
model::Servo& servo_on(const Port& port, std::int64_t id);

/// The servo a request addresses ("port" and "servo"), its motion brought up to now.
model::Servo& addressed(Target& target, const Args& args);

}  // namespace dxlemu::control
