#pragma once

#include <cstdint>
#include <filesystem>
#include <nlohmann/json_fwd.hpp>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "app/config/model_library.hpp"
#include "app/config/physics_config.hpp"
#include "model/spec/model_error.hpp"
#include "wire/protocol.hpp"

namespace dxlemu::app {

/// The highest ID a servo may be given (0xFD and up are not servo IDs in either protocol).
inline constexpr int kMaxServoId = 252;

/// One servo of a port: a model from the library, its ID, and items to set at power-on (by key,
/// e.g. baud_rate, return_delay_time, protocol_type), as if written before the emulator started.
struct ServoConfig {
  std::string model;
  std::uint8_t id = 1;
  /// Item values in the order they are applied (raw item values, as the control table holds them).
  std::vector<std::pair<std::string, std::int64_t>> items;
  bool operator==(const ServoConfig&) const = default;
};

/// The longest latency timer a USB serial adapter takes, in ms (FTDI: 1 ~ 255; 0 is no adapter).
inline constexpr int kMaxAdapterLatencyMs = 255;
/// The adapter chip dxlemu models unless told otherwise: a U2D2's FT232H.
inline constexpr const char* kDefaultAdapterChip = "ft232h";

/// Data bytes per USB packet of the adapter chip `chip` ("ft232h", "ft232r"), or nullopt for
/// another name (docs/timing.md "USB adapter latency").
std::optional<std::size_t> adapter_packet_data(std::string_view chip);
/// The chip names adapter_packet_data() knows, for messages: "ft232h, ft232r".
std::string adapter_chip_names();

/// The longest port name: names appear in logs, traces and control-API requests.
inline constexpr std::size_t kMaxPortName = 32;

/// The longest joint name a port may give (docs/config.md "Joints").
inline constexpr std::size_t kMaxJointName = 40;
/// How far a joint's range may reach either way from the middle of its servo's position range,
/// in degrees: eight turns, more than any servo's multi-turn mode is asked to go by a robot.
inline constexpr double kMaxJointRangeDeg = 360.0 * 8;

/// What a robot's software calls the servo at `id` of a port (its motor or joint name, e.g.
/// LeRobot's "shoulder_pan"), and the joint's mechanical range where it is known.
struct JointName {
  std::string name;
  std::uint8_t id = 1;
  /// (low, high): the joint's mechanical range as the servo's shaft sees it, in degrees from the
  /// middle of the servo's position range (2048 on a 4096-pulse servo, 512 on an XL-320),
  /// positive towards higher positions; absent when no source gives it.
  std::optional<std::pair<double, double>> range_deg;
  bool operator==(const JointName&) const = default;
};

/// A hand a port starts with (`--hand`, a port's "hand"; docs/hands.md): a control request,
/// hand.play or hand.sweep, as JSON text without its "port", and where it was given.
struct HandStart {
  std::string request;
  /// For messages: "--hand pick.csv", "my.json: /ports/0/hand".
  std::string origin;
  bool operator==(const HandStart&) const = default;
};

/// One port: a PTY with an optional stable symlink, and its servos in bus order.
struct PortConfig {
  std::string name;
  std::optional<std::filesystem::path> link;
  std::vector<ServoConfig> servos;
  /// The USB serial adapter's latency timer on this port in ms, 0 for none; when absent, the
  /// command line's --adapter-latency-ms.
  std::optional<int> adapter_latency_ms;
  /// The adapter's chip on this port; when absent, the command line's --adapter-chip.
  std::optional<std::string> adapter_chip;
  /// The names the robot's software gives the servos of this port, in file order; at most one
  /// per ID, each ID a servo of `servos`.
  std::vector<JointName> joints;
  /// The hands that hold its joints from the start, in order.
  std::vector<HandStart> hands;
  /// The robot profile this port is part of (its name); empty for a plain config's port.
  std::string robot;
  bool operator==(const PortConfig&) const = default;
};

/// A robot's part in teleoperation: the leader is moved by a hand, the follower copies it.
enum class RobotRole { Leader, Follower };

/// "leader" or "follower", as profiles spell it.
std::string_view robot_role_name(RobotRole role);

/// The header of a robot profile (docs/robots.md): which robot this bus is, and where each of its
/// facts was read. Only descriptive: the ports and servos say what is served.
struct RobotHeader {
  std::string name;                  ///< the name `--robot` takes, the profile's file name
  std::string title;                 ///< one line for `dxlemu robots`
  std::vector<std::string> sources;  ///< URLs of the public files the profile's facts come from
  std::string software;              ///< what drives the robot; empty when not given
  std::vector<std::string> notes;    ///< free text, one paragraph per entry
  std::optional<RobotRole> role;     ///< leader or follower of a teleoperation pair; absent: none
  /// The profile of the other half of its pair (opposite role, naming this one back, checked by
  /// RobotLibrary::load); empty: none.
  std::string pairs_with;
  bool operator==(const RobotHeader&) const = default;
};

/// The longest robot name a profile may have.
inline constexpr std::size_t kMaxRobotName = 40;

/// Everything `dxlemu run` serves: one or more ports, and optionally a physics world their
/// servos drive (docs/physics.md).
struct BusConfig {
  std::vector<PortConfig> ports;
  std::optional<PhysicsConfig> physics;
  /// The robot header of a robot profile; absent in a plain config.
  std::optional<RobotHeader> robot;
  bool operator==(const BusConfig&) const = default;
};

/// A config the emulator refuses. what() reads "FILE: POINTER: REASON", as for model files.
class ConfigError : public model::ModelError {
 public:
  using ModelError::ModelError;
};

/// Parses and validates a bus config (format: docs/config.md) against `library`: every model
/// exists, every item override names an item of that model, is writable and in range, baud and
/// protocol shorthands are possible on the model. `origin` names the file in errors. Throws
/// ConfigError naming the JSON pointer of the first problem.
BusConfig parse_config(const std::string& text, const std::string& origin,
                       const ModelLibrary& library);

/// The JSON document `text` of file `origin`; ConfigError (pointer "") when it is not JSON.
nlohmann::json parse_json(const std::string& text, const std::string& origin);

/// The text of file `path`; ConfigError when it cannot be read.
std::string read_text_file(const std::filesystem::path& path);

/// Reads and parses the config file `path`; ConfigError also when it cannot be read.
BusConfig read_config(const std::filesystem::path& path, const ModelLibrary& library);

/// The Baud Rate item value that selects `bps` on `spec`. Throws std::invalid_argument naming
/// the rates the model offers.
std::int64_t baud_rate_item_value(const model::ModelSpec& spec, std::uint32_t bps);

/// The item override that makes `spec` speak `protocol`: Protocol Type (or Protocol Version on
/// MX-64/106(2.0)) set to the protocol's Protocol Type value (1, 2; Modbus RTU 10); nothing for a
/// model without such an item that speaks `protocol`. Throws std::invalid_argument for a model
/// whose file does not list `protocol`, naming the models of `library` that can speak it.
std::optional<std::pair<std::string, std::int64_t>> protocol_item(const model::ModelSpec& spec,
                                                                  wire::Protocol protocol,
                                                                  const ModelLibrary& library);

/// The models of `library` that can speak `protocol`, for a refusal: "ph42-020-s300-r, ..."; at
/// most a dozen names, then how many more (`dxlemu models --protocol` lists them all).
std::string models_speaking(wire::Protocol protocol, const ModelLibrary& library);

/// The protocol a `"protocol"` member of a config or robot profile names: 1 or 2 (DYNAMIXEL's
/// numbers), or the spelling of a protocol without a number ("feetech", "modbus"); nullopt for
/// anything else.
std::optional<wire::Protocol> protocol_of_json(const nlohmann::json& value);

/// The protocol `servo` speaks once its item overrides applied: the last Protocol Type (or
/// Protocol Version) override's, else the model's factory protocol (the first it lists).
wire::Protocol configured_protocol(const ServoConfig& servo, const model::ModelSpec& spec);

/// Checks `servo`'s ID against the IDs of the protocol it speaks (configured_protocol): Modbus
/// RTU takes 1 ~ 247 (the slave addresses), DYNAMIXEL 0 ~ 252. Throws std::invalid_argument
/// naming the servo, the protocol and the range.
void check_servo_id(const ServoConfig& servo, const model::ModelSpec& spec);

/// Checks `servo` against `library`: the model exists and every item override names a writable
/// item of it and lies in that item's range. Throws std::invalid_argument with the reason (for
/// servos built from command-line options; parse_config checks the same with JSON pointers).
void check_servo(const ServoConfig& servo, const ModelLibrary& library);

/// Checks that every servo of `port` is one maker's: a port speaks DYNAMIXEL's protocols or
/// FEETECH's, never both (docs/feetech.md "One maker per port"). Returns the index of the first
/// servo of another maker than the first servo's, or nullopt; unknown models are skipped
/// (check_servo names them).
std::optional<std::size_t> other_maker_servo(const PortConfig& port, const ModelLibrary& library);

/// The reason other_maker_servo() refuses servo `index` of `port`, for an error message.
std::string other_maker_reason(const PortConfig& port, std::size_t index,
                               const ModelLibrary& library);

}  // namespace dxlemu::app
