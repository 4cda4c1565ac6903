#pragma once

#include <catch2/catch.hpp>

#include <nlohmann/json.hpp>
#include <string>

#include "control/api.hpp"

namespace dxlemu::test {

/// Requests to a control::Api as one-line JSON, for unit-test rigs: `Rig` derives from
/// ApiRequests<Rig> and has a member `api`.
template <class Rig>
class ApiRequests {
 public:
  /// The whole reply to `line`, parsed.
  nlohmann::json reply(const std::string& line) {
    return nlohmann::json::parse(static_cast<Rig*>(this)->api.handle(line));
  }
  /// The result of a request that must succeed.
  nlohmann::json result(const std::string& line) {
    const nlohmann::json r = reply(line);
    INFO(line << " -> " << r.dump());
    REQUIRE(r["ok"] == true);
    return r["result"];
  }
  /// The error text of a request that must fail.
  std::string error(const std::string& line) {
    const nlohmann::json r = reply(line);
    INFO(line << " -> " << r.dump());
    REQUIRE(r["ok"] == false);
    return r["error"].get<std::string>();
  }
};

}  // namespace dxlemu::test
