"""Every choice the FEETECH sources leave open, as data, each with the note the model carries.
A note starts with the field it concerns ("initial: ...", "sign_bit: ...")."""

from __future__ import annotations

from dataclasses import dataclass, field

KG_CM_NM = 0.0980665  # 1 kgf·cm in N·m

# FEETECH's Baud Rate codes as every wiki table and SDK header states them (0~7: the tables'
# range); Part 2 of the protocol page and FTServo_Arduino INST.h go on to 11.
FEETECH_BAUDS = [1000000, 500000, 250000, 128000, 115200, 76800, 57600, 38400]
BAUD_NOTE = ("baud_rates: codes 0~7 as FEETECH's table prints them: 1000000(0), 500000(1), 250000(2), "
             "128000(3), 115200(4), 76800(5), 57600(6), 38400(7) (every SDK header agrees). The protocol "
             "page's Part 2 and FTServo_Arduino INST.h add 8=19200, 9=14400, 10=9600, 11=4800 beyond the "
             "table's range 0~7, so they are not listed. lerobot's baud table differs at 5~7 (57600: 5, "
             "38400: 6, 19200: 7); lerobot only ever writes code 0 (1 Mbps)")
TIMING = {"ping_us": 50, "read_us": 50, "write_us": 50, "write_per_byte_us": 0, "boot_ms": 1800}
TIMING_NOTE = ("timing: no FEETECH source gives a processing time before a reply; 50 us for ping, read and "
               "write (the figure the DYNAMIXEL Protocol 2.0 models use) until one is measured")
BOOT_NOTE = "timing.boot_ms: 1800, the protocol page's Restart instruction: 'restart time about 1800ms'"
RETURN_DELAY_NOTE = ("return_delay_unit_us: 2 (SMS table 'Response return delay', unit 2us; the ST3215 "
                     "spreadsheet 'Return delay', unit 2us)")
PROTOCOL_NOTE = ("protocols: the FT-SCS protocol (feetech/protocol-ft-scs.md); listed in models/feetech/catalog.json, "
                 "FEETECH's catalog beside DYNAMIXEL's models/catalog.json")
MODEL_NUMBER_NOTE = ("size: the wiki prints 3 'Servo major version' and 4 'Servo minor version', "
                     "1 byte each; every SDK (MODEL_L 3 / MODEL_H 4) and lerobot (Model_Number (3, 2)) read one "
                     "2-byte word there, which Ping's model check compares, so the model has one 2-byte item "
                     "in the model's byte order")


@dataclass
class Family:
    """What one FEETECH series shares: its wiki table's reference, byte order, and the items whose
    key, encoding or range the table does not give directly."""
    name: str
    byte_order: str
    # address -> key, where snake_case of the wiki's name would not do
    keys: dict[int, str]
    # address -> (sign bit or None, note): overrides what the description's "BITn is the
    # direction bit" says
    sign_bits: dict[int, tuple[int | None, str]]
    # address -> ((min, max), note): a range the Range cell does not give
    ranges: dict[int, tuple[tuple[int, int], str]]
    # address -> (values, note)
    values: dict[int, tuple[list[int], str]]
    # address -> (initial or the key to copy at power-on, note), for the initial cells that
    # print '–' or a sentence; a model's own entry wins
    initials: dict[int, tuple[int | str, str]]
    # rows the wiki marks Undefined/Reserved that the model still has: address -> item fields
    added: dict[int, dict] = field(default_factory=dict)
    # model-level notes of every model of the series
    notes: list[str] = field(default_factory=list)


@dataclass
class Model:
    """One FEETECH model: its facts and the choices made for it."""
    name: str
    title: str
    reference: str            # file in ../shared/reference/feetech/
    family: str
    model_number: int
    model_number_note: str
    firmware: tuple[int, int, str]   # major, minor, note
    degrees_per_pulse: float
    velocity_unit_rpm: float
    motion_notes: list[str]
    stall_torque_kgcm: float
    nominal_voltage_v: float
    spec_note: str
    current_unit_ma: float | None
    initials: dict[int, tuple[int | str, str]] = field(default_factory=dict)
    notes: list[str] = field(default_factory=list)


_PHASE_NOTE = ("initial: the wiki prints '–'; 12, the ST3215 spreadsheet's value (BIT2 speed unit 0.0146RPM = "
               "1 step/s, BIT3 speed 0 means the highest speed), for every STS and SMS model")
_RETURN_DELAY = {"key": "return_delay_time", "name": "Return delay", "size": 1, "access": "RW", "area": "EEPROM",
                 "initial": 0, "min": 0, "max": 254, "unit": "2us",
                 "note": "address: the wiki marks 7 'Reserved' (STS) or 'Undefined' (SCSCL); the ST3215 spreadsheet "
                         "has 'Return delay' 0~254, unit 2us, initial 0, and lerobot 'Return_Delay_Time' (7, 1), "
                         "which its configure_motors() writes 0 to; every servo needs a return delay item, so the "
                         "model has the spreadsheet's. lerobot's comment that the default is 250 (500 us) matches "
                         "no FEETECH source"}

# Values of STS/SMS items the wiki leaves '–', from the ST3215 spreadsheet (the only source with
# model values), used for every model of the two series that share the SMS_STS SDK layer.
_STS_SMS_INITIALS: dict[int, tuple[int | str, str]] = {
    14: (80, "initial: the wiki prints '–'; 80 (8.0 V), the ST3215 spreadsheet's value"),
    18: (12, _PHASE_NOTE),
    19: (44, "initial: the wiki prints '–'; 44, the ST3215 spreadsheet's value (overheat, overcurrent, load "
             "protection)"),
    20: (47, "initial: the wiki prints '–'; 47, the ST3215 spreadsheet's value"),
    21: (32, "initial: the wiki prints '–'; 32, the ST3215 spreadsheet's value (lerobot's LeKiwi: 'Default is 32')"),
    22: (32, "initial: the wiki prints '–'; 32, the ST3215 spreadsheet's value (lerobot's LeKiwi: default 32)"),
    24: (16, "initial: the wiki prints '–'; 16, the ST3215 spreadsheet's value"),
    37: (10, "initial: the wiki prints '–'; 10, the ST3215 spreadsheet's value"),
    39: (10, "initial: the wiki prints '–'; 10, the ST3215 spreadsheet's value"),
    46: (0, "initial: the wiki prints 'Factory default maximum speed'; 0, which its description says 'means the "
            "maximum speed by default' (the ST3215 spreadsheet: initial 0)"),
    48: ("maximum_torque", "initial: the wiki prints 'Maximum torque (16), default 1000': copied from Maximum torque at "
                       "power-on"),
    56: (2048, "initial: the wiki prints '–'; 2048, the middle of 0~4095 (a servo at rest in mid position)"),
    58: (0, "initial: the wiki prints '–'; 0, at rest"),
    60: (0, "initial: the wiki prints '–'; 0, at rest"),
    63: (25, "initial: the wiki prints '–'; 25 °C, room temperature"),
    69: (0, "initial: the wiki prints '–'; 0, at rest"),
    **{a: (0, "initial: the wiki prints '–' for the factory parameters; 0 until a servo is read")
       for a in range(77, 87)},
}

_STS_SMS_SIGN_BITS: dict[int, tuple[int | None, str]] = {
    31: (11, "sign_bit: 11 (lerobot's encoding table: Homing_Offset 11; the ST3215 spreadsheet: 'Bit11 "
             "is the direction bit', -2047~2047). The wiki's range 0~8191 maps 2048~4095 to 0~-2047, which is "
             "bit 11 as the sign; its 4096~8191 pieces ('bias -4095~4095') have no sign-magnitude reading and "
             "are refused"),
    69: (15, "sign_bit: sign_bit 15: the wiki gives none, but every SDK's ReadCurrent tests bit 15"),
}

_LEROBOT_85 = ("lerobot: Maximum_Acceleration (85, 1) is the wiki's factory parameter 'Acceleration limit', access R; "
               "lerobot's configure_motors() writes 254 to it (protocol 0), a write the model refuses as read-only "
               "(no FEETECH source says what a servo does with it)")
_LEROBOT_SIGNS = ("lerobot: its sign-magnitude table (Present_Load 10, Homing_Offset 11, Goal/Present position and "
                  "velocity 15) has no entry for PWM open-loop speed (44, the wiki's 'BIT10 is the direction bit') "
                  "or Present current (69, bit 15 in the SDK's ReadCurrent), which the model encodes too")

# Maximum angle limit: the tables print 1~4095, yet say the value "is 0 when the multi turn
# absolute position control is adopted"; the description wins (docs/feetech.md "Motion").
_MULTI_TURN_MAX_LIMIT = ((0, 4095), "range: 0~4095; the table prints 1~4095, but its description says the "
                                    "value is 0 in multi-turn absolute position control")

FAMILIES = {
    "sts": Family(
        name="sts", byte_order="little",
        keys={5: "id", 67: "current_goal_position"},
        sign_bits=_STS_SMS_SIGN_BITS,
        ranges={31: ((-2047, 2047), "range: -2047~2047, see sign_bit"), 11: _MULTI_TURN_MAX_LIMIT},
        values={40: ([0, 1, 2, 128], "values: 0~2, and 128, which the description says calibrates the present "
                                     "position to 2048")},
        initials=_STS_SMS_INITIALS,
        added={7: _RETURN_DELAY},
        notes=[_LEROBOT_85, _LEROBOT_SIGNS,
               "lerobot: Hts (83, 1) '(ns) valid for firmware >= 2.54' is the SMS table's meaning of 83; the STS "
               "table's 83 is 'Minimum speed limit', which the model follows"]),
    "sms": Family(
        name="sms", byte_order="little",
        keys={5: "id", 7: "return_delay_time", 67: "current_goal_position"},
        sign_bits=_STS_SMS_SIGN_BITS,
        ranges={31: ((-2047, 2047), "range: -2047~2047, see sign_bit"), 11: _MULTI_TURN_MAX_LIMIT,
                7: ((0, 253), "range: the wiki prints '0/50~253' and 'a setting below 50 still defaults to 50 "
                              "(100us)', so 0~253 is accepted and values below 50 act as 50 (its text's "
                              "'maximum settable return delay 254*2=508us' is not followed)")},
        values={40: ([0, 1, 2, 128], "values: 0~2, and 128, which the description says calibrates the present "
                                     "position to 2048")},
        initials=_STS_SMS_INITIALS,
        notes=[_LEROBOT_85, _LEROBOT_SIGNS]),
    "scs": Family(
        name="scs", byte_order="big",
        keys={5: "id"},
        sign_bits={
            44: (None, "sign_bit: none: the wiki's Running time is 0~9999 ms in position mode and, 'in motor "
                       "mode', a PWM duty -1000~1000 with 'BIT10 is the direction bit'; raw 0~9999 holds both "
                       "(bit 10 set is 1024~2024), so the item is unsigned and motor mode reads bit 10 itself"),
            58: (15, "sign_bit: sign_bit 15: the wiki gives none, but the SDK's SCSCL::ReadSpeed tests bit 15"),
        },
        ranges={44: ((0, 9999), "range: the wiki prints '0~9999/-1000~1000' (position mode / motor mode): 0~9999, "
                                "see sign_bit")},
        values={},
        initials={
            14: (80, "initial: the wiki prints '–'; 80 (8.0 V), above the model's 4-7.4V operating range"),
            18: (0, "initial: the wiki prints '–'; 0 (every phase bit at its (0) setting)"),
            19: (44, "initial: the wiki prints '–'; 44 as the ST3215 spreadsheet (the same bit meanings)"),
            20: (47, "initial: the wiki prints '–'; 47 as the ST3215 spreadsheet (the same bit meanings)"),
            21: (32, "initial: the wiki prints '–'; 32 as the ST3215 spreadsheet"),
            22: (32, "initial: the wiki prints '–'; 32 as the ST3215 spreadsheet"),
            24: (16, "initial: the wiki prints '–'; 16 as the ST3215 spreadsheet"),
            46: (0, "initial: the wiki prints 'Factory default maximum speed'; 0, which makes Running time decide "
                    "('effective when the running speed is 0')"),
            56: (512, "initial: the wiki prints '–'; 512, the middle of 0~1023 (150°)"),
            58: (0, "initial: the wiki prints '–'; 0, at rest"),
            60: (0, "initial: the wiki prints '–'; 0, at rest"),
            63: (25, "initial: the wiki prints '–'; 25 °C, room temperature"),
            82: (0, "initial: the wiki prints '–' for this factory parameter; 0 until a servo is read"),
        },
        added={7: _RETURN_DELAY}),
    "hls": Family(
        name="hls", byte_order="little",
        keys={5: "id", 67: "current_goal_position"},
        sign_bits={
            44: (15, "sign_bit: sign_bit 15, the wiki's constant-current mode (2) direction bit; in PWM mode (3) "
                     "it says 'the write range is -1000~1000 and BIT10 is the direction bit', which the motion "
                     "model must read from the raw value"),
        },
        ranges={11: _MULTI_TURN_MAX_LIMIT},
        values={},
        initials={
            14: (80, "initial: the wiki prints '–'; 80 (8.0 V) as the 7.4 V ST3215 spreadsheet"),
            18: (0, "initial: the wiki prints '–'; 0 (every phase bit at its (0) setting)"),
            19: (44, "initial: the wiki prints '–'; 44 as the ST3215 spreadsheet"),
            20: (47, "initial: the wiki prints '–'; 47 as the ST3215 spreadsheet"),
            21: (32, "initial: the wiki prints '–'; 32 as the ST3215 spreadsheet"),
            22: (32, "initial: the wiki prints '–'; 32 as the ST3215 spreadsheet"),
            24: (16, "initial: the wiki prints '–'; 16 as the ST3215 spreadsheet"),
            28: (511, "initial: the wiki prints '–'; 511, the STS and SMS tables' value"),
            34: (0, "initial: the wiki prints '–' and no range; 0"),
            35: (0, "initial: the wiki prints '–' and no range; 0"),
            37: (10, "initial: the wiki prints '–'; 10 as the ST3215 spreadsheet"),
            39: (10, "initial: the wiki prints '–'; 10 as the ST3215 spreadsheet"),
            44: ("protection_current", "initial: the wiki prints 'Protection current (28)': copied at power-on"),
            46: (0, "initial: the wiki prints 'Factory default maximum speed'; 0 (the wiki: '0 means stop')"),
            48: ("maximum_torque", "initial: the wiki prints 'Maximum torque (16)': copied at power-on"),
            50: ("position_loop_p_coefficient",
                 "initial: the wiki prints 'Position loop P coefficient (21) / velocity loop P coefficient (37)': "
                 "copied from 21, position servo mode being the initial Operating mode 0"),
            51: ("position_loop_d_coefficient", "initial: the wiki prints 'Position loop D coefficient (22)': copied"),
            52: ("velocity_loop_i_coefficient", "initial: the wiki prints 'Velocity loop I coefficient (39)': copied"),
            56: (2048, "initial: the wiki prints '–'; 2048, the spec sheet's 'Neutral Position 180° (2048)'"),
            58: (0, "initial: the wiki prints '–'; 0, at rest"),
            60: (0, "initial: the wiki prints '–'; 0, at rest"),
            63: (25, "initial: the wiki prints '–'; 25 °C, room temperature"),
            67: (0, "initial: the wiki prints '–'; 0 as Goal position (42)"),
            69: (0, "initial: the wiki prints '–'; 0, at rest"),
            73: (0, "initial: the wiki prints '–'; 0"),
            **{a: (0, "initial: the wiki prints '–' for the factory parameters; 0 until a servo is read")
               for a in range(77, 87)},
        }),
}

_STS_FW = (3, 6, "firmware_version: 3, the major version; items 0/1 (major/minor) start at 3/6, the ST3215 "
                 "spreadsheet's 'Firmware major/sub version number'")

MODELS = [
    Model(name="sts3215", title="STS3215", reference="sts3215.md", family="sts", model_number=777,
          model_number_note="model_number: 777, lerobot's MODEL_NUMBER_TABLE (no FEETECH page states it); the "
                            "ST3215 spreadsheet's initial values 9 (address 3) and 3 (address 4) make the same "
                            "little-endian word",
          firmware=_STS_FW, degrees_per_pulse=360 / 4096, velocity_unit_rpm=60 / 4096,
          motion_notes=["motion.degrees_per_pulse: 360/4096 (spec sheet 'Running degree: 360° (when 0~4096)'; "
                        "lerobot resolution 4096)",
                        "motion.velocity_unit_rpm: 60/4096 = 1 step/s, the unit with Phase BIT2 set as in the "
                        "ST3215 spreadsheet's Phase 12 ('50 steps / second = 0.732 RPM'); with BIT2 clear the "
                        "wiki's unit is 0.732 RPM"],
          stall_torque_kgcm=19, nominal_voltage_v=7.4,
          spec_note="the model page ST-3215-C001: 'Stall torque 19 kg·cm@7.4V', 'Input voltage 7.4 V' (the 12 V "
                    "ST-3215-C018 states 30 kg·cm@12V); no no-load speed or stall current is stated",
          current_unit_ma=6.5,
          initials={62: (74, "initial: the wiki prints '–'; 74, the supply at the model's 7.4 V")}),
    Model(name="sts3250", title="STS3250", reference="sts3250.md", family="sts", model_number=2825,
          model_number_note="model_number: 2825, lerobot's MODEL_NUMBER_TABLE (no FEETECH page states it)",
          firmware=(3, 6, "firmware_version: 3; items 0/1 start at 3/6 as the ST3215 spreadsheet (no STS3250 "
                          "source gives a version)"),
          degrees_per_pulse=360 / 4096, velocity_unit_rpm=60 / 4096,
          motion_notes=["motion.degrees_per_pulse: 360/4096 (lerobot resolution 4096; the STS table's 0.087°)",
                        "motion.velocity_unit_rpm: 60/4096 = 1 step/s, the unit of the Phase 12 chosen for "
                        "STS models (see items.phase)"],
          stall_torque_kgcm=50, nominal_voltage_v=12.0,
          spec_note="the model page ST-3250-C001: 'Stall torque 50 kg·cm@12V', 'Input voltage 9–12.6 V'",
          current_unit_ma=6.5,
          initials={14: (140, "initial: the wiki prints '–'; 140 (14.0 V), above the model's 9–12.6 V"),
                    62: (120, "initial: the wiki prints '–'; 120, the supply at the model's 12 V")}),
    Model(name="sm8512bl", title="SM8512BL", reference="sm8512bl.md", family="sms", model_number=11272,
          model_number_note="model_number: 11272, lerobot's MODEL_NUMBER_TABLE (no FEETECH page states it)",
          firmware=(3, 6, "firmware_version: 3; items 0/1 start at 3/6 as the ST3215 spreadsheet (no SMS source "
                          "gives a version)"),
          degrees_per_pulse=360 / 4096, velocity_unit_rpm=60 / 4096,
          motion_notes=["motion.degrees_per_pulse: 360/4096 (spec sheet '360° (when 0~ 4095)'; lerobot "
                        "resolution 4096)",
                        "motion.velocity_unit_rpm: 60/4096 = 1 step/s, the unit of the Phase 12 chosen for "
                        "SMS models as for STS"],
          stall_torque_kgcm=85, nominal_voltage_v=12.0,
          spec_note="the model page SM-8512-C001: 'Stall torque 85 kg·cm@12V', spec sheet 'Operating Voltage "
                    "Range 12V'",
          current_unit_ma=6.5,
          initials={14: (140, "initial: the wiki prints '–'; 140 (14.0 V), above the model's 9–12.6 V"),
                    62: (120, "initial: the wiki prints '–'; 120, the supply at the model's 12 V")},
          notes=["default_baud_index: 0 (1 Mbps), the SMS table's initial value; its text says 'the SMS baud rate "
                 "is 115200' (code 4), which the table contradicts",
                 "items.operating_mode: range 0~2 as the SMS table prints it, although its description lists "
                 "'3: step mode' (the STS table: 0~3)"]),
    Model(name="scs0009", title="SCS0009", reference="scs0009.md", family="scs", model_number=1284,
          model_number_note="model_number: 1284 (0x0504), lerobot's MODEL_NUMBER_TABLE (no FEETECH page states "
                            "it); big-endian, so address 3 holds 0x05 and 4 holds 0x04",
          firmware=(3, 6, "firmware_version: 3; items 0/1 start at 3/6 as the ST3215 spreadsheet (no SCS source "
                          "gives a version)"),
          degrees_per_pulse=300 / 1024, velocity_unit_rpm=300 / 1024 / 360 * 60,
          motion_notes=["motion.degrees_per_pulse: 300/1024 (spec sheet 'Position Sensor Resolution: "
                        "0.293°(300°/1024)'; lerobot resolution 1024)",
                        "motion.velocity_unit_rpm: 1 step/s (the wiki's Running speed unit 'Step/s') = "
                        "300/1024/360*60 rev/min"],
          stall_torque_kgcm=2.3, nominal_voltage_v=6.0,
          spec_note="the model page SC-0090-C001: 'Stall torque 2.3 kg·cm@6V', 'Input voltage 6 V'",
          current_unit_ma=None,
          initials={62: (60, "initial: the wiki prints '–'; 60, the supply at the model's 6 V")},
          notes=["items: Present current (69~70) is in every SDK and the wiki's older SCSCL summary but not in "
                 "its current table, which the model follows; the SCSCL table has no Operating mode item "
                 "('minimum angle limit = maximum angle limit = 0 enters motor mode')",
                 "lerobot: no sign-magnitude encoding for SCS models (MODEL_ENCODING_TABLE['scs0009'] = {}); the "
                 "model follows the wiki and the SDK (Present load bit 10, Present speed bit 15)",
                 "lerobot: protocol_version 1 (= big-endian in the SDK); it refuses Sync Read and broadcast Ping "
                 "for these models, and the protocol page says Sync Read 'is available for some serial bus "
                 "servos'"]),
    Model(name="hls3625m", title="HLS3625M", reference="hls3625.md", family="hls", model_number=266,
          model_number_note="model_number: 266 (0x010A) is a choice: no source states an HLS model number. The "
                            "wiki's 'Servo major version' (3) starts at 10, the low byte; 'Servo minor version' "
                            "(4) prints '–' and is taken as 1, the smallest that collides with no model in the "
                            "library (10 is RX-10's). A real HLS3625M may report another number",
          firmware=(3, 43, "firmware_version: 3, the wiki's 'Firmware major version' initial value; the minor "
                           "version (1), '–' in the wiki (range 40 ~ 59), starts at 43, the first firmware with "
                           "the position calibration instruction 0x0B (the protocol page: HLS fw >= 3.43)"),
          degrees_per_pulse=360 / 4096, velocity_unit_rpm=0.732,
          motion_notes=["motion.degrees_per_pulse: 360/4096 (spec sheet 'Resolution 0.088°(360°/4096)')",
                        "motion.velocity_unit_rpm: 0.732, the wiki's Running speed unit '0.732RPM'"],
          stall_torque_kgcm=25, nominal_voltage_v=7.4,
          spec_note="the model page HL-3625-C001: 'Stall torque 25 kg·cm@7.4V', 'Input voltage 7.4 V'",
          current_unit_ma=6.5,
          initials={62: (74, "initial: the wiki prints '–'; 74, the supply at the model's 7.4 V")},
          notes=["items: the HLS table has no return delay item (its address 7 is the Secondary ID), and the "
                 "model has none: a FEETECH model may lack return_delay_time, and then answers without a "
                 "return delay (docs/feetech.md)",
                 "lerobot: no HLS support"]),
]
