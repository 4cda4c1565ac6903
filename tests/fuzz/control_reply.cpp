#include "control_reply.hpp"

#include <cstdint>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <vector>

#include "fuzz_require.hpp"

namespace dxlemu::fuzz {
namespace {

// An allocator no other code uses, so that every nlohmann template this file instantiates is its
// own: the linker cannot pick the coverage-instrumented copy of dxlemu's ordered_json instead.
template <class T>
struct CheckerAllocator : std::allocator<T> {
  using value_type = T;
  CheckerAllocator() = default;
  template <class U>
  explicit CheckerAllocator(const CheckerAllocator<U>& /*other*/) {}
  template <class U>
  struct rebind {
    using other = CheckerAllocator<U>;
  };
};

using CheckerJson = nlohmann::basic_json<std::map, std::vector, std::string, bool, std::int64_t,
                                         std::uint64_t, double, CheckerAllocator>;

}  // namespace

bool check_control_reply(std::string_view request, const std::string& reply) {
  FUZZ_REQUIRE(reply.find('\n') == std::string::npos);
  const CheckerJson parsed = CheckerJson::parse(reply, nullptr, false);
  FUZZ_REQUIRE_MSG(!parsed.is_discarded(), "reply %s", reply.c_str());
  FUZZ_REQUIRE(parsed.is_object());
  FUZZ_REQUIRE(parsed.contains("id"));
  FUZZ_REQUIRE(parsed.contains("ok") && parsed["ok"].is_boolean());
  const bool ok = parsed["ok"].get<bool>();
  if (ok) {
    FUZZ_REQUIRE(parsed.contains("result"));
    FUZZ_REQUIRE(!parsed.contains("error"));
  } else {
    FUZZ_REQUIRE(parsed.contains("error") && parsed["error"].is_string());
    FUZZ_REQUIRE(!parsed["error"].get<std::string>().empty());
    FUZZ_REQUIRE(!parsed.contains("result"));
  }
  // "id is echoed as given (any JSON value); it is null when the request has none or could not
  // be parsed."
  const CheckerJson sent = CheckerJson::parse(request, nullptr, false);
  const bool has_id = !sent.is_discarded() && sent.is_object() && sent.contains("id");
  FUZZ_REQUIRE_MSG(parsed["id"] == (has_id ? sent["id"] : CheckerJson()), "request %.*s reply %s",
                   static_cast<int>(request.size()), request.data(), reply.c_str());
  return ok;
}

}  // namespace dxlemu::fuzz
