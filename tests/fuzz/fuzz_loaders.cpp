// libFuzzer target for the file loaders on arbitrary text: model::parse_model (model files,
// docs/model-format.md), app::parse_config (bus configs, docs/config.md) and
// app::parse_trajectory (trajectory files, both formats). Each either accepts the text or refuses
// it with its documented error type (ModelError, ConfigError) naming a JSON pointer (a trajectory
// file: a line) and a reason; any other exception escapes and is reported as a crash. What a
// loader accepts must also be usable: a model builds a servo, a config's servos build on a bus, a
// trajectory samples within its keyframes' values.

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <stdexcept>
#include <string>
#include <string_view>

#include "app/config/bus_config.hpp"
#include "app/config/model_library.hpp"
#include "app/config/trajectory_file.hpp"
#include "fuzz_require.hpp"
#include "model/hand/trajectory.hpp"
#include "model/servo.hpp"
#include "model/spec/model_error.hpp"
#include "model/spec/model_loader.hpp"

namespace dxlemu::fuzz {
namespace {

const app::ModelLibrary& library() {
  static const app::ModelLibrary lib = app::ModelLibrary::load(DXLEMU_MODELS_DIR, {});
  return lib;
}

// An RFC 6901 pointer: empty (the whole document) or "/"-separated reference tokens.
bool is_json_pointer(const std::string& pointer) {
  return pointer.empty() || pointer.front() == '/';
}

void check_refusal(const model::ModelError& error, const std::string& origin) {
  FUZZ_REQUIRE(error.origin() == origin);
  FUZZ_REQUIRE_MSG(is_json_pointer(error.pointer()), "pointer '%s'", error.pointer().c_str());
  FUZZ_REQUIRE(!error.reason().empty());
  FUZZ_REQUIRE(std::string_view(error.what()).starts_with(origin + ": "));
}

void fuzz_model(const std::string& text) {
  const std::string origin = "fuzz/model.json";
  std::shared_ptr<const model::ModelSpec> spec;
  try {
    spec = std::make_shared<const model::ModelSpec>(model::parse_model(text, origin));
  } catch (const model::ModelError& error) {
    check_refusal(error, origin);
    return;
  }
  // An accepted model is one the emulator can run: a servo of it powers on and reboots. The one
  // refusal left to the servo: the items every servo needs (the loader does not require them;
  // the daemon reports the servo's std::out_of_range, which names the model and the item).
  const bool has_identity = spec->find("id") != nullptr && spec->find("baud_rate") != nullptr &&
                            spec->find("return_delay_time") != nullptr;
  try {
    model::Servo servo(spec, spec->default_id);
    servo.reboot();
  } catch (const std::out_of_range&) {
    FUZZ_REQUIRE(!has_identity);
  }
}

void fuzz_config(const std::string& text) {
  const std::string origin = "fuzz/config.json";
  app::BusConfig config;
  try {
    config = app::parse_config(text, origin, library());
  } catch (const app::ConfigError& error) {
    check_refusal(error, origin);
    return;
  }
  FUZZ_REQUIRE(!config.ports.empty());
  // As app::Emulator builds the ports: the item overrides were checked, so setting them cannot
  // throw.
  for (const app::PortConfig& port : config.ports) {
    for (const app::ServoConfig& servo : port.servos) {
      const auto spec = library().find(servo.model);
      FUZZ_REQUIRE(spec != nullptr);
      FUZZ_REQUIRE(servo.id <= app::kMaxServoId);
      model::Servo built(spec, servo.id);
      for (const auto& [key, value] : servo.items) {
        built.table().set(key, value);
      }
      built.commit_deferred();
    }
  }
}

// Samples of each column at a few times, both interpolations: every value within the column's
// keyframe values, every rate finite.
FUZZ_NO_COVERAGE void check_samples(const model::Trajectory& trajectory) {
  constexpr int kSteps = 8;
  for (std::size_t c = 0; c < trajectory.columns().size(); ++c) {
    const auto values = trajectory.column_values(c);
    const auto [lo, hi] = std::minmax_element(values.begin(), values.end());
    for (int i = 0; i <= kSteps; ++i) {
      const double t = trajectory.duration_s() * i / kSteps;
      for (const auto interpolation : {model::Interpolation::Linear, model::Interpolation::Cubic}) {
        const auto sample = trajectory.at(c, t, interpolation);
        FUZZ_REQUIRE_MSG(sample.value >= *lo && sample.value <= *hi, "column %zu at %g s: %g", c, t,
                         sample.value);
        FUZZ_REQUIRE(std::isfinite(sample.rate_per_s));
      }
    }
  }
}

void fuzz_trajectory(const std::string& text, app::TrajectoryFormat format) {
  const std::string origin = "fuzz/trajectory";
  try {
    check_samples(app::parse_trajectory(text, origin, format));
  } catch (const app::ConfigError& error) {
    FUZZ_REQUIRE(error.origin() == origin);
    FUZZ_REQUIRE_MSG(error.pointer() == "end of file" || error.pointer().starts_with("line "),
                     "pointer '%s'", error.pointer().c_str());
    FUZZ_REQUIRE(!error.reason().empty());
  }
}

}  // namespace
}  // namespace dxlemu::fuzz

/// libFuzzer's entry point: the input is the text of a file, given to every loader.
// NOLINTNEXTLINE(readability-identifier-naming): the name libFuzzer calls
extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  // NOLINTNEXTLINE(cppcoreguidelines-pro-type-reinterpret-cast): libFuzzer gives bytes
  const std::string text(reinterpret_cast<const char*>(data), size);
  dxlemu::fuzz::fuzz_model(text);
  dxlemu::fuzz::fuzz_config(text);
  dxlemu::fuzz::fuzz_trajectory(text, dxlemu::app::TrajectoryFormat::Csv);
  dxlemu::fuzz::fuzz_trajectory(text, dxlemu::app::TrajectoryFormat::JsonLines);
  return 0;
}
