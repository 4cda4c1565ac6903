#pragma once

#include <string>
#include <string_view>

namespace dxlemu::fuzz {

/// Checks that `reply` is what docs/control-api.md promises for `request`: one line of JSON, an
/// object with a boolean "ok", "result" when true, a non-empty "error" string when false, and
/// the request's "id" echoed (null when the request has none or is not a JSON object). Aborts
/// through FUZZ_REQUIRE otherwise; returns "ok".
///
/// Compiled without coverage instrumentation and with a JSON type of its own (control_reply.cpp):
/// parsing every reply again is the checker's work, not dxlemu's, and instrumented it was a
/// quarter of fuzz_control's time.
bool check_control_reply(std::string_view request, const std::string& reply);

}  // namespace dxlemu::fuzz
