// Model-layer behaviours that fuzz_bus and fuzz_loaders (tests/fuzz/) found wrong, each
// reproduced with the input the fuzzer's boiled down to.
#include <catch2/catch.hpp>
#include <memory>
#include <string>

#include "model/servo.hpp"
#include "model/spec/model_error.hpp"
#include "model/spec/model_loader.hpp"
#include "shipped_model.hpp"
#include "wire/packet_encoder.hpp"
#include "wire/status_error.hpp"

using namespace dxlemu;
using wire::Protocol;

TEST_CASE("A 1.0 Read of more than a 1.0 status can carry is refused with Range Error",
          "[servo][fuzz]") {
  // An X in 1.0 mode has a table long enough for a Read of 254 or 255 bytes, but a 1.0 status
  // carries at most 253 (LENGTH = parameters + 2 in one byte): encoding the status threw out of
  // Bus::receive, which ended the daemon.
  model::Servo servo(test::shipped_model("xm430-w350"), 7);
  servo.table().set("protocol_type", 1);
  servo.commit_deferred();
  REQUIRE(servo.protocol() == Protocol::V1);

  const auto longest =
      servo.execute({Protocol::V1, 7, wire::Read{0, 253}}, model::Addressing::Unicast);
  CHECK(longest.error == 0);
  CHECK(longest.params.size() == 253);
  for (const std::uint16_t length : {254, 255}) {
    const auto r =
        servo.execute({Protocol::V1, 7, wire::Read{36, length}}, model::Addressing::Unicast);
    CHECK(r.replies);
    CHECK(r.error == wire::v1_error::kRange);
    CHECK(r.params.empty());
    CHECK_NOTHROW(wire::encode_status({Protocol::V1, 7, r.error, r.params}));
  }
}

TEST_CASE("A model file with a number too large for a double is refused with a ModelError",
          "[model_loader][fuzz]") {
  // nlohmann::json reports "1e999" as out_of_range, not parse_error: it escaped parse_model as
  // a plain json exception instead of the ModelError that names the file and the reason.
  for (const std::string text : {R"({"name": 1e999})", "[-6e666666]"}) {
    try {
      model::parse_model(text, "big.json");
      FAIL("accepted " << text);
    } catch (const model::ModelError& e) {
      CHECK(e.origin() == "big.json");
      CHECK(e.pointer().empty());
      CHECK_THAT(e.reason(),
                 Catch::StartsWith("not valid JSON: ") && Catch::Contains("number overflow"));
    }
  }
}
