// libFuzzer target for the control API (docs/control-api.md): each line of the input is one
// request to control::Api::handle against ports of real servos on a hand-stepped clock. Every
// request gets exactly one line of JSON, an object with "ok" (and "error" when false, "result"
// when true) and the request's "id" echoed; afterwards the target still answers a plain request.

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "control/api.hpp"
#include "control_reply.hpp"
#include "control_target.hpp"
#include "fuzz_require.hpp"

namespace dxlemu::fuzz {
namespace {

// scenario.load {"file": PATH} reads a file: keep the fuzzer away from device files and the
// kernel's pseudo files, where a read may never end.
bool touches_special_files(std::string_view text) {
  for (const std::string_view prefix : {"/dev", "/proc", "/sys"}) {
    if (text.find(prefix) != std::string_view::npos) {
      return true;
    }
  }
  return false;
}

// Two ports, so that requests must name one: dxl0 as in the documentation's examples (servos 1,
// 2, 3), dxl1 with a 2.0 model of another family. Few servos: building them is most of the
// target's own time per input.
void build(ControlTarget& target) {
  ControlTarget::Port& dxl0 = target.add_port("dxl0");
  target.add(dxl0, "xm430-w350", 1);
  target.add(dxl0, "xm430-w350", 2);
  target.add(dxl0, "ax-12a", 3);
  ControlTarget::Port& dxl1 = target.add_port("dxl1");
  target.add(dxl1, "xl-320", 4);
}

}  // namespace
}  // namespace dxlemu::fuzz

/// libFuzzer's entry point: one input, one fresh target; each line of the input is a request.
// NOLINTNEXTLINE(readability-identifier-naming): the name libFuzzer calls
extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace dxlemu::fuzz;
  // NOLINTNEXTLINE(cppcoreguidelines-pro-type-reinterpret-cast): libFuzzer gives bytes
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  if (touches_special_files(text)) {
    return -1;  // not added to the corpus
  }
  ControlTarget target;
  build(target);
  dxlemu::control::Api api(target);
  dxlemu::control::Connection client{1, [](const std::string& /*line*/) {}};
  std::size_t start = 0;
  while (start <= text.size()) {
    const std::size_t end = std::min(text.find('\n', start), text.size());
    const std::string_view line = text.substr(start, end - start);
    // Each request from its own connection now and then, so trace subscriptions vary.
    check_control_reply(line, api.handle(line, &client));
    client.id = client.id % 3 + 1;
    start = end + 1;
  }
  // Whatever came before, the target still answers a plain request.
  const std::string list = R"({"id": 1, "cmd": "list"})";
  FUZZ_REQUIRE(check_control_reply(list, api.handle(list, &client)));
  return 0;
}
