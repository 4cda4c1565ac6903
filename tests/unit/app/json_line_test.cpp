// JsonLine (app/record/json_line.hpp): the trace's JSON lines, written as nlohmann::json writes
// them.
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>
#include <string>

#include "app/record/json_line.hpp"

using dxlemu::app::JsonLine;

namespace {

// What nlohmann writes for a one-member object holding `value` (the reference for the format).
template <typename T>
std::string nlohmann_line(const T& value) {
  return nlohmann::ordered_json{{"k", value}}.dump(-1, ' ', false,
                                                   nlohmann::json::error_handler_t::replace);
}

}  // namespace

TEST_CASE("JsonLine writes members in order, as one object", "[app][trace]") {
  CHECK((JsonLine{}.text("a", "x").integer("b", -3).real("c", 0.5).finish()) ==
        R"({"a":"x","b":-3,"c":0.5})");
  CHECK(JsonLine{}.finish() == "{}");
}

TEST_CASE("JsonLine escapes text as nlohmann::json does", "[app][trace]") {
  for (const std::string& value :
       {std::string("plain"), std::string("quote \" and \\ backslash"),
        std::string("tab\tnew\nline\rform\fback\b"), std::string("\x01\x1f control", 10),
        std::string("caf\xc3\xa9 \xe2\x82\xac"), std::string("bad \xff\xfe utf-8"),
        std::string("nul \0 inside", 12)}) {
    INFO(value);
    CHECK(JsonLine{}.text("k", value).finish() == nlohmann_line(value));
  }
}

TEST_CASE("JsonLine writes numbers as nlohmann::json does", "[app][trace]") {
  for (const double value : {0.0, 2.0, 0.0015, 0.004465424, 1e-05, 123456.789012345, 1e20}) {
    INFO(value);
    CHECK(JsonLine{}.real("k", value).finish() == nlohmann_line(value));
  }
  for (const std::int64_t value :
       {std::int64_t{0}, std::int64_t{255}, std::int64_t{-1}, std::int64_t{9007199254740993}}) {
    INFO(value);
    CHECK(JsonLine{}.integer("k", value).finish() == nlohmann_line(value));
  }
}
