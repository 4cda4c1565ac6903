#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "control/connection.hpp"
#include "control/samplers.hpp"
#include "control/target.hpp"
#include "sim/sim_time.hpp"

namespace dxlemu::control {

/// The longest clock.step: simulated time that one request may run (a servo in motion costs a
/// motion tick per millisecond of it).
inline constexpr sim::SimDuration kMaxStep = std::chrono::hours(1);

/// The control API's commands, without any I/O: one request line in, one reply line out. The
/// io/ class that owns the Unix socket calls handle() with each line it reads.
///
/// Request: a JSON object `{"id": 7, "cmd": "get", ...arguments}`. Reply: `{"id": 7, "ok": true,
/// "result": ...}` or `{"id": 7, "ok": false, "error": "what is wrong"}`. "id" is echoed as given
/// (any JSON value) and is null when the request had none or could not be parsed. Unknown
/// arguments are refused, to catch typos. Commands and their arguments: docs/control-api.md.
class Api {
 public:
  /// An API acting on `target`, which must outlive it.
  explicit Api(Target& target);

  /// Handles one request from `connection` (null: none): `line` is JSON without its newline.
  /// Returns the reply as one line of JSON without the newline. Never throws: a malformed
  /// request gets an error reply.
  std::string handle(std::string_view line, const Connection* connection = nullptr);

  /// Runs a request already parsed (a scenario step) from `connection` (null: none); returns the
  /// reply object. Never throws.
  nlohmann::ordered_json run(const nlohmann::ordered_json& request,
                             const Connection* connection = nullptr);

  /// What is wrong with `request` (unknown command or argument, a bad fault rule, an unknown
  /// port or servo), found without running it; nullopt when nothing is.
  static std::optional<std::string> check(Target& target, const nlohmann::ordered_json& request);

  /// The command names, in the order `help` lists them.
  static std::vector<std::string> command_names();

  /// Ends everything connection `connection` (its id) had: its trace subscription and its
  /// sampler. The transports call it when a connection closes; no event reaches it afterwards.
  void closed(std::uint64_t connection);

 private:
  Target& target_;
  // What lasts between requests: each connection's sampler (sample.subscribe).
  Samplers samplers_;
};

}  // namespace dxlemu::control
