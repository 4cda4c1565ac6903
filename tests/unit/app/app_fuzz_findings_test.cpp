// Config loading behaviours that fuzz_loaders (tests/fuzz/) found wrong, each reproduced with the
// text the fuzzer's input boiled down to.
#include <catch2/catch.hpp>
#include <string>

#include "app/config/bus_config.hpp"
#include "app/config/model_library.hpp"

using namespace dxlemu;

TEST_CASE("A config with a number too large for a double is refused with a ConfigError",
          "[config][fuzz]") {
  // nlohmann::json reports "1e999" as out_of_range, not parse_error: it escaped parse_config as
  // a plain json exception instead of the ConfigError that names the file and the reason.
  const app::ModelLibrary library = app::ModelLibrary::load(DXLEMU_MODELS_DIR, {});
  const std::string text =
      R"({"ports": [{"name": "dxl0", "servos": [{"model": "xm430-w350", "id": 1e999}]}]})";
  try {
    app::parse_config(text, "bus.json", library);
    FAIL("accepted " << text);
  } catch (const app::ConfigError& e) {
    CHECK(e.origin() == "bus.json");
    CHECK(e.pointer().empty());
    CHECK_THAT(e.reason(),
               Catch::StartsWith("not valid JSON: ") && Catch::Contains("number overflow"));
  }
}
