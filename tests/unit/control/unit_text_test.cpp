// Reading a model file's unit text as a factor and a unit (control/unit_text.hpp), for `table`:
// the forms the shipped model files use, and the ones that are not "NUMBER [UNIT]".
#include <catch2/catch.hpp>

#include <set>
#include <string>

#include "control/unit_text.hpp"
#include "model/spec/model_spec.hpp"
#include "shipped_model.hpp"

using dxlemu::control::scaled_unit;
using dxlemu::control::scaled_value;
using dxlemu::control::ScaledUnit;

TEST_CASE("A unit NUMBER (UNIT in brackets) reads as a factor and a unit", "[control][unit_text]") {
  CHECK(scaled_unit("0.229 [rev/min]") == ScaledUnit{0.229, "rev/min"});
  CHECK(scaled_unit("58,000 [rev/min²]") == ScaledUnit{58000, "rev/min²"});
  CHECK(scaled_unit("1[pulse]") == ScaledUnit{1, "pulse"});
  CHECK(scaled_unit("1 [pulse]") == ScaledUnit{1, "pulse"});
  CHECK(scaled_unit("1.0 [mA]") == ScaledUnit{1, "mA"});
  CHECK(scaled_unit("1 [°C]") == ScaledUnit{1, "°C"});
  CHECK(scaled_unit("0.00199234 [rev/min]") == ScaledUnit{0.00199234, "rev/min"});
  CHECK(scaled_unit("1,234,567.5 [x]") == ScaledUnit{1234567.5, "x"});
}

TEST_CASE("FEETECH's unit NUMBERUNIT, without brackets, reads the same way",
          "[control][unit_text]") {
  CHECK(scaled_unit("0.1V") == ScaledUnit{0.1, "V"});
  CHECK(scaled_unit("6.5mA") == ScaledUnit{6.5, "mA"});
  CHECK(scaled_unit("0.087°") == ScaledUnit{0.087, "°"});
  CHECK(scaled_unit("8.7°/s²") == ScaledUnit{8.7, "°/s²"});
  CHECK(scaled_unit("1%") == ScaledUnit{1, "%"});
  CHECK(scaled_unit("2us") == ScaledUnit{2, "us"});
  CHECK_FALSE(scaled_unit("0.732RPM/0.0146RPM"));  // two figures: a ratio
  CHECK_FALSE(scaled_unit("1ms/0.1%"));
  CHECK_FALSE(scaled_unit("Step"));
  CHECK_FALSE(scaled_unit("°C"));
  CHECK_FALSE(scaled_unit("ID"));
  CHECK_FALSE(scaled_unit("1 m A"));
}

TEST_CASE("A unit in any other form has no factor", "[control][unit_text]") {
  CHECK_FALSE(scaled_unit(""));
  CHECK_FALSE(scaled_unit("R"));
  CHECK_FALSE(scaled_unit("1/R"));
  CHECK_FALSE(scaled_unit("16.11328 mA]"));                 // the '[' is missing
  CHECK_FALSE(scaled_unit("214.577 [rev/min²] / 1 [ms]"));  // a ratio of two units
  CHECK_FALSE(scaled_unit("0.229 [rev/min] / 1 [msec]"));
  CHECK_FALSE(scaled_unit("1 [pulse"));
  CHECK_FALSE(scaled_unit("1 []"));
  CHECK_FALSE(scaled_unit("0 [V]"));  // no factor scales by 0
  CHECK_FALSE(scaled_unit("1. [V]"));
  CHECK_FALSE(scaled_unit("1,00 [V]"));  // commas group thousands only
  CHECK_FALSE(scaled_unit(",100 [V]"));
  CHECK_FALSE(scaled_unit("-1 [V]"));
  CHECK_FALSE(scaled_unit("about 0.229 [rev/min]"));
  CHECK_FALSE(scaled_unit("[rev/min]"));
}

TEST_CASE(
    "Every unit of the shipped models either scales as its figure says or is a known "
    "other form",
    "[control][unit_text]") {
  auto models = dxlemu::test::catalog_models();
  for (const char* feetech : {"sts3215", "sts3250", "scs0009", "sm8512bl", "hls3625m"}) {
    models.push_back(dxlemu::test::shipped_model(std::string("feetech/") + feetech));
  }
  // What the model files write that is not "NUMBER [UNIT]": shown as written, unscaled.
  const std::set<std::string> others = {"R",
                                        "1/R",
                                        "16.11328 mA]",
                                        "214.577 [rev/min²] / 1 [ms]",
                                        "214.577 [rev/min2] / 1 [msec]",
                                        "214.577 [rev/min2] / 1 [ms]",
                                        "0.229 [rev/min] / 1 [msec]",
                                        "0.732RPM/0.0146RPM",
                                        "1ms/0.1%",
                                        "ID",
                                        "Step",
                                        "Step/s",
                                        "°C"};
  std::set<std::string> unscaled;
  std::size_t scaled = 0;
  for (const auto& spec : models) {
    for (const auto& item : spec->items) {
      if (item.unit.empty()) {
        continue;
      }
      CAPTURE(spec->name, item.key, item.unit);
      if (const auto read = scaled_unit(item.unit)) {
        ++scaled;
        // The same figure the motion model reads from the unit ("58,000" aside).
        if (item.unit.find(',') == std::string::npos) {
          CHECK(read->factor == dxlemu::model::unit_figure(item.unit));
        }
        CHECK(!read->unit.empty());
        CHECK(read->unit.find_first_of("[]") == std::string::npos);
      } else {
        unscaled.insert(item.unit);
      }
    }
  }
  CHECK(unscaled == others);
  CHECK(scaled > 1000);
}

TEST_CASE("A scaled value drops the product's binary noise", "[control][unit_text]") {
  CHECK(scaled_value(2048, 0.229) == 468.992);
  CHECK(scaled_value(1023, 0.00199234) == 2.03816382);
  CHECK(scaled_value(-5, 2.69) == -13.45);
  CHECK(scaled_value(100, 58000) == 5800000);
  CHECK(scaled_value(0, 0.229) == 0);
  CHECK(scaled_value(4294967295, 0.229) == 983547510.555);
  CHECK(scaled_value(-2147483648, 1) == -2147483648.0);
}
