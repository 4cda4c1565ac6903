#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <vector>

#include "model/motion/motion_model.hpp"
#include "model/spec/model_spec.hpp"
#include "model/table/control_table.hpp"
#include "sim/sim_time.hpp"
#include "wire/instruction.hpp"
#include "wire/instruction_decoder.hpp"

namespace dxlemu::model {

/// How an instruction reached a servo: by its ID, by the broadcast ID, or by its Secondary
/// (Shadow) ID, which executes RAM changes silently (docs/servo.md).
enum class Addressing { Unicast, Broadcast, Secondary };

/// What a servo answers to one instruction, before the bus frames and times it.
struct ServoResponse {
  bool replies = false;    ///< false: the servo stays silent
  std::uint8_t error = 0;  ///< the status ERR byte in the servo's protocol (2.0: number | alert)
  std::vector<std::uint8_t> params;
  /// Time from the end of the instruction on the wire to the start of the reply, before Return
  /// Delay Time (the model's processing time for this kind of instruction).
  sim::SimDuration processing{};
  /// The servo reboots once its status is out (Reboot, Factory Reset, Backup restore).
  bool reboot_after = false;
};

/// One virtual servo: its control table and the state the e-Manual gives a device beyond it (the
/// Reg Write slot, the Control Table Backup, identity changes waiting for the status to go out).
/// It executes instructions addressed to it; the bus decides who is addressed and when replies go
/// out. Rules and choices: docs/servo.md.
class Servo {
 public:
  /// A servo of `spec` at factory settings, except for `id`, whose motion model ticks every
  /// `tick` of simulated time.
  Servo(std::shared_ptr<const ModelSpec> spec, std::uint8_t id,
        sim::SimDuration tick = std::chrono::milliseconds(1));
  // The control table's hooks point into the servo: it stays where it was made.
  Servo(const Servo&) = delete;
  Servo& operator=(const Servo&) = delete;

  const ModelSpec& spec() const { return table_.spec(); }
  ControlTable& table() { return table_; }
  const ControlTable& table() const { return table_; }
  /// The motion model: conditions, injected hardware errors, the motor's state. Call wake() on
  /// it after changing the table device-side.
  MotionModel& motion() { return motion_; }
  const MotionModel& motion() const { return motion_; }

  /// Brings motion, temperature and hardware errors up to `now` (simulated time). The bus calls
  /// it before the servo sees an instruction.
  void advance_to(sim::SimTime now) { motion_.advance_to(now); }

  /// Identity on the bus. A new ID, Baud Rate, Protocol Type or Return Delay Time written by an
  /// instruction takes effect only at commit_deferred(), after that instruction's status.
  std::uint8_t id() const { return id_; }
  /// The protocol the servo speaks now; nullopt when Protocol Type has just selected a
  /// non-DYNAMIXEL protocol (XL330 S.BUS / iBUS / RC-PWM): it answers nothing on the bus until it
  /// reboots, and then speaks 2.0 because no RC signal is present.
  std::optional<wire::Protocol> protocol() const { return protocol_; }
  /// The bit rate the servo listens at.
  std::uint32_t baud_bps() const { return baud_bps_; }
  /// Return Delay Time as a duration.
  sim::SimDuration return_delay() const { return return_delay_; }

  /// Executes Ping, Read, Write, Reg Write, Action, Factory Reset, Reboot, Clear, Control Table
  /// Backup or an unknown instruction addressed to this servo. Applies Status Return Level and
  /// the broadcast and Secondary ID rules to decide whether it replies.
  ServoResponse execute(const wire::InstructionPacket& packet, Addressing addressing);

  /// The Secondary (Shadow) ID when it is active (0 ~ 252), else nullopt.
  std::optional<std::uint8_t> secondary_id() const;

  /// The Bus Watchdog period while it is armed (Torque Enable 1 and Bus Watchdog 1 ~ 127, in
  /// 20 ms units), else nullopt (includes/control_table_buswatchdog.md).
  std::optional<sim::SimDuration> bus_watchdog_period() const;

  /// No instruction packet for a whole Bus Watchdog period: the servo stops (Goal Velocity 0,
  /// Goal Position held at Present Position) and Bus Watchdog becomes -1, which refuses goal
  /// writes with Data Range Error until 0 is written.
  void expire_bus_watchdog();

  /// The answer to an instruction whose parameters could not be decoded (error status, unless
  /// broadcast, suppressed by Status Return Level, or a refusal the model answers with silence).
  ServoResponse refuse(const wire::DecodeError& error, bool broadcast) const;

  /// The answer to an instruction packet with a wrong CRC (2.0: CRC Error) or checksum (1.0:
  /// Checksum Error bit; FEETECH: silence by default), sent to this servo's ID; `instruction` is
  /// the unverified instruction byte.
  ServoResponse bad_check(std::optional<std::uint8_t> instruction) const;

  /// True when Status Return Level lets the servo answer a read (`is_read`) or anything else.
  bool replies_to(bool is_read) const;

  /// True for the models that take part in Fast Sync/Bulk Read (protocol2.md: X430/540 except
  /// 2XL/2XC, X330, P).
  bool supports_fast_read() const;

  /// True for the models that execute the Protocol 1.0 Bulk Read (protocol1.md: MX, MX(2.0), X).
  bool supports_v1_bulk_read() const;

  /// This servo's part of a Sync/Bulk Read (or Fast), and a Read's: its data, or an error and no
  /// data, or (`replies` false) no status at all where the model answers a read outside its
  /// table with silence.
  ServoResponse read_part(std::uint16_t address, std::uint16_t length);

  /// This servo's part of a Sync/Bulk Write: applied like a Write, never answered.
  void write_part(std::uint16_t address, std::span<const std::uint8_t> data);

  /// Applies the ID, Baud Rate, Protocol Type and Return Delay Time the control table holds now.
  void commit_deferred();

  /// Reboot or power cycle: RAM back to initial values (or the backup, if Startup Configuration
  /// asks for it), the Reg Write slot emptied, identity refreshed (an RC Protocol Type falls back
  /// to 2.0, as with no RC signal at boot).
  void reboot();

  /// How long the servo is silent after a reboot or power-on while it boots (its model's timing).
  sim::SimDuration boot_time() const;

  /// Its power is cut (unplugged): the motor gives no torque. The servo keeps its table until it
  /// is powered on again, which is a reboot().
  void power_off();

  /// True when the last Control Table Backup store succeeded and has not been lost.
  bool has_backup() const { return backup_.has_value(); }

  /// Device side (the control API's set): puts `value` into item `item_index` as if the device
  /// itself had changed it. A value a Write instruction could store there goes in as that Write
  /// (its hooks run: a goal starts a move, Torque Enable holds the shaft where it is); anything
  /// else (read-only items, EEPROM while locked, values out of range, Indirect Data) is forced
  /// into the image, which no hook hears. The motion model then follows the new value, and a
  /// deferred item (defers()) takes effect at once. Throws std::invalid_argument if the value
  /// does not fit the item's size, std::out_of_range for an unknown item.
  void device_write(std::size_t item_index, std::int64_t value);

  /// How many times a bus instruction wrote EEPROM item `item_index` since the servo was made
  /// (Write, Sync Write, Bulk Write, Action of a Reg Write; whether or not the value changed):
  /// what wears its flash. Device-side changes (device_write, a state file), Factory Reset and
  /// the restores of a backup are not counted. 0 for any other item.
  std::uint64_t eeprom_writes(std::size_t item_index) const {
    return item_index < eeprom_writes_.size() ? eeprom_writes_[item_index] : 0;
  }

  /// True for the items whose new value applies only at commit_deferred(): ID, Baud Rate,
  /// Return Delay Time and Protocol Type (Protocol Version on MX(2.0)).
  bool defers(std::size_t item_index) const;

 private:
  wire::DeviceFaults device_faults() const;
  std::uint8_t status_error(wire::Outcome outcome) const;
  /// The answer of `outcome`: its status error byte, or no status where the servo answers that
  /// refusal with silence (a FEETECH model's refusals).
  ServoResponse respond(wire::Outcome outcome, sim::SimDuration processing) const;
  ServoResponse from_table(const TableResult& result, sim::SimDuration processing) const;
  ServoResponse do_factory_reset(std::uint8_t option, bool broadcast);
  ServoResponse execute_secondary(const wire::InstructionPacket& packet);
  ServoResponse do_clear(const wire::Clear& clear);
  ServoResponse do_backup(const wire::ControlTableBackup& backup);
  /// FEETECH's own instructions (servo_feetech.cpp).
  ServoResponse execute_feetech(const wire::StatusReset& reset);
  ServoResponse execute_feetech(const wire::ParameterBackup& backup);
  ServoResponse execute_feetech(const wire::ParameterRecovery& recovery);
  ServoResponse execute_feetech(const wire::PositionCalibration& calibration);
  /// FEETECH's Lock flag is 0: EEPROM writes persist, and backup/recovery may run.
  bool feetech_eeprom_unlocked() const;
  sim::SimDuration write_time(std::size_t bytes) const;
  /// A write an instruction carried: the table's bus_write, with every EEPROM item it wrote
  /// counted (eeprom_writes()). Every instruction's write goes through here, device-side ones not.
  TableResult instruction_write(std::uint16_t address, std::span<const std::uint8_t> data,
                                wire::Protocol protocol);
  std::optional<std::size_t> item(std::initializer_list<std::string_view> keys) const;
  /// True when the servo has `item` and the protocol it speaks now reaches it (absent_in).
  bool speaks_item(const std::optional<std::size_t>& item) const;

  ControlTable table_;
  MotionModel motion_;
  /// Items read on every packet, looked up once: a key lookup scans the model's items.
  struct KeyItems {
    std::size_t id = 0;
    std::size_t baud_rate = 0;
    std::optional<std::size_t> return_delay_time;  // FEETECH HLS has none
    std::optional<std::size_t> protocol;           // Protocol Type (Protocol Version on MX(2.0))
    std::optional<std::size_t> hardware_error_status;  // DYNAMIXEL-Y: Error Code
    std::optional<std::size_t> status_return_level;
    std::optional<std::size_t> secondary_id;
    std::optional<std::size_t> bus_watchdog;
    std::optional<std::size_t> torque_enable;  // FEETECH: Torque switch
    std::optional<std::size_t> registered;     // FEETECH: Async write flag
  };
  KeyItems items_;
  std::uint8_t id_ = 1;
  std::optional<wire::Protocol> protocol_;
  std::uint32_t baud_bps_ = 0;
  sim::SimDuration return_delay_{};
  struct Registered {
    std::uint16_t address;
    std::vector<std::uint8_t> data;
  };
  std::optional<Registered> registered_;
  std::vector<std::uint64_t> eeprom_writes_;         // by item index: eeprom_writes()
  std::optional<std::vector<std::uint8_t>> backup_;  // the whole byte image when stored
  /// FEETECH Parameter backup: the byte image Parameter recovery restores.
  std::optional<std::vector<std::uint8_t>> parameter_backup_;
};

}  // namespace dxlemu::model
