"""Item-level decisions, as data: the power-on values of items the pages print as '-', which
items are signed, the accepted values of Operating Mode, Protocol Type and Baud Rate where the
table's range is not the answer, bounds between items, ranges widened so that the factory value
is accepted, and where MX(2.0) pages borrow their ranges. Each entry carries its note.
"""

from __future__ import annotations

from dataclasses import dataclass

from . import EMANUAL_INCLUDES
from .catalogue import P2_FAMILIES, V1_FAMILIES
from .model_fields import EXTERNAL_BAUD

# ---------------------------------------------------------------------------------------------
# Power-on values
# ---------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class InitialRule:
    """The power-on value of an item whose Initial Value cell is not a number ('-', 'Max Torque').

    Exactly one of `value`, `copy_from` and `computed` is set. A rule that does not apply (its
    `printed` pattern does not match, or nothing to compute from) leaves the item to ZERO_REASONS.
    """
    note: str                  # the item's note; {what} is the printed text, {value} the value chosen
    value: int | None = None   # a fixed value
    copy_from: str = ""        # initial_from: the item whose value is copied at power-on
    computed: str = ""         # a value item_builder computes (its INITIAL_COMPUTATIONS)
    printed: str = ""          # regex the printed text must match (case-insensitive), "" for any


_MID_POSITION = InitialRule(
    "initial: the page shows '-' (the position at power-on is not known to the table); {value} (mid-range "
    "/ centre of travel) chosen, inside the range and the position limits", computed="mid_position")
_SUPPLY_VOLTAGE = InitialRule(
    "initial: the page shows '-'; {value} (midpoint of the factory Min/Max Voltage Limit {low} ~ {high}) "
    "chosen as a plausible supply voltage", computed="supply_voltage")

INITIAL_RULES = {
    "firmware_version": InitialRule("initial: the page shows '-'; the model's firmware_version ({value})",
                                    computed="firmware_version"),
    "id": InitialRule("initial: the page shows '1, 2' (axis 1 and axis 2 of the dual-axis module); 1 is "
                      "stored here and the emulator gives the second axis ID 2", value=1, printed=r"1,\s*2"),
    "model_information": InitialRule("initial: the page shows '-' and does not describe the contents; 0 chosen",
                                     value=0),
    "torque_limit": InitialRule("initial: the page shows {what}; Torque Limit takes the value of Max Torque at "
                                "power-on (Torque Limit description: 'the value of Max Torque ... is used as "
                                "the initial value'; MX-12W prints 'ADD 14&15', the address of Max Torque)",
                                copy_from="max_torque", printed=r"max torque|-|add 14\s*&(amp;)?\s*15"),
    "goal_pwm": InitialRule("initial: the page shows '-'; Goal PWM starts at PWM Limit (the X/MX(2.0) Goal PWM "
                            "block's range row reads 'Initial Value of PWM Limit', and switching Operating Mode "
                            "resets Goal PWM to PWM Limit)", copy_from="pwm_limit"),
    "goal_current": InitialRule("initial: the page shows '-'; Goal Current starts at Current Limit (switching "
                                "Operating Mode resets Goal Current to Current Limit, opmode block)",
                                copy_from="current_limit"),
    "goal_position": _MID_POSITION,
    "present_position": _MID_POSITION,
    "position_trajectory": _MID_POSITION,
    "present_input_voltage": _SUPPLY_VOLTAGE,
    "present_voltage": _SUPPLY_VOLTAGE,
    "present_temperature": InitialRule("initial: the page shows '-'; 25 (room temperature, deg C) chosen",
                                       value=25),
    "present_inverter_temperature": InitialRule("initial: the page shows '-'; 25 (room temperature, deg C) chosen",
                                                value=25),
    "present_motor_temperature": InitialRule("initial: the page shows '-'; 25 (room temperature, deg C) chosen",
                                             value=25),
    "moving_status": InitialRule(
        "initial: the page shows '-'; {value} (Position In Range, bit 6: Present Position at power-on lies within "
        "Min/Max Position Limit; not moving, no profile) chosen "
        f"({EMANUAL_INCLUDES}y/control_table_541_moving_status.md)", computed="moving_status_at_rest"),
    "controller_state": InitialRule(
        "initial: the page shows '-'; 2 (Inverter OFF, 'Torque OFF state. The inverter is turned OFF.') chosen: the "
        "servo powers on with Torque Enable 0 and passes Start (0) and Init System (1) before it answers "
        f"({EMANUAL_INCLUDES}y/control_table_152_controller_state.md)", value=2),
    "acceleration_limit": InitialRule("initial: the page shows '-'; {value:,} (the top of the range, so the "
                                      "factory setting refuses no Goal Acceleration) chosen", computed="range_top"),
    "velocity_limit": InitialRule("initial: the page shows '-'; 1,023 chosen, the top of the Goal Velocity range its "
                                  "description states ('-1,023 ~ 1,023 (0x3FF) can be used', L42-10-S300-R), so the "
                                  "factory setting refuses no documented Goal Velocity", value=1023),
    "sensed_current": InitialRule("initial: the page shows '-'; 512 ('512 is equal to 0mA', description) chosen",
                                  value=512),
}

# Printed factory values the reference itself contradicts: (page, key) -> (value, note).
_XW430_PROTOCOL = (2, "initial: the page prints 1, but its own Protocol Type block (control_table_protocolversion.md) "
                      "lists '2(default) | DYNAMIXEL Protocol 2.0 | ... X Series' and the Protocol Compatibility "
                      "Table marks the XW430's Protocol 1.0 'O* (F/W address 13)', configuration required: the "
                      "servo ships speaking 2.0, as every X servo, and 2 is used")
INITIAL_OVERRIDES = {
    ("xw430-t200", "protocol_type"): _XW430_PROTOCOL,
    ("xw430-t333", "protocol_type"): _XW430_PROTOCOL,
}

# PRO(A) pages print '-' for the gains and Bus Watchdog. A PRO(A) servo is the DYNAMIXEL-P of the
# same motor under its earlier "PRO+" name (the reference README: h54p-200-s500-r etc. are "earlier
# 'PRO+' names of the PH/PM pages"; the PRO(A) pages pull `en/dxl/pro_plus/` includes), and both
# tables have these items at the same addresses: the P page's factory value is used.
TWIN_PAGES = {
    "h42-20-s300-ra": "ph42-020-s300-r", "h54-100-s500-ra": "ph54-100-s500-r",
    "h54-200-s500-ra": "ph54-200-s500-r", "m42-10-s260-ra": "pm42-010-s260-r",
    "m54-40-s250-ra": "pm54-040-s250-r", "m54-60-s250-ra": "pm54-060-s250-r",
}
_FROM_TWIN = InitialRule("initial: the page shows '-'; {value} is the factory value the DYNAMIXEL-P page of the "
                         "same servo prints at this address (control-tables/{twin}.md; PRO(A) = the P series' "
                         "earlier 'PRO+' firmware, TWIN_PAGES)", computed="twin_page")
for _key in ("velocity_i_gain", "velocity_p_gain", "position_d_gain", "position_i_gain", "position_p_gain",
             "feedforward_1st_gain", "feedforward_2nd_gain", "bus_watchdog"):
    INITIAL_RULES[_key] = _FROM_TWIN

# The centre of travel per family, the power-on value of the position items.
MID_POSITION = {"x": 2048, "mx2": 2048, "mx1": 2048, "ex": 2048, "ax": 512, "rx": 512, "xl320": 512,
                "p": 0, "pro": 0,
                # DYNAMIXEL-Y: factory Min/Max Position Limit -262,144 ~ 262,144 around 0
                "y": 0}

# Why 0 is the power-on value of the other items the pages print as "-" (key pattern, reason).
ZERO_REASONS = [
    (r"goal_velocity", "motor at rest; Goal Velocity is only used once a velocity mode is commanded"),
    (r"moving_speed", "0 means 'maximum speed, no speed control' in joint mode and stop in wheel mode"),
    (r"realtime_tick", "the millisecond counter starts at power-on"),
    (r"moving|moving_status", "not moving at power-on"),
    (r"present_(pwm|current|velocity|load|speed)|velocity_trajectory", "motor at rest at power-on"),
    (r"backup_ready", "no Control Table Backup exists in the factory state"),
    (r"error_code", f"0 is 'No Error' ({EMANUAL_INCLUDES}y/control_table_153_error_code.md)"),
    (r"error_code_history_\d+", "no error has occurred in the factory state"),
    (r"external_port_data_\d+", "nothing connected / outputs low at power-on"),
    (r"profile_(acceleration|velocity)", "no profile, as on the X pages, whose initial value is 0"),
    (r"bus_watchdog", "0 deactivates the Bus Watchdog (control_table_buswatchdog.md: '0 | Deactivate Bus Watchdog "
                      "Function'), the factory state of every page that prints a value"),
    (r"(velocity|position)_[pid]_gain|feedforward_(1st|2nd)_gain",
     "the factory gains are stated nowhere in the reference (no page of the same firmware prints them); "
     "dxlemu's motion model does not use the gains, so the value only answers a read"),
]

# Keys of misspelt names: the item the emulator knows by the right key (Secondary ID behaviour is
# read from `secondary_id`).
KEY_ALIASES = {
    "sencondary_id": ("secondary_id", "key: the page misspells the name 'Sencondary ID'; the item is Secondary "
                                      "ID (its description section is 'Secondary ID(12)'), keyed secondary_id"),
}

# Pages stored only in an older revision, and the rows they lack that a newer page of the same
# table prints (the reference README: "Older stored revisions only ... no Startup Configuration(60)
# / Backup Ready(878) rows"). DynamixelSDK 4.0.5's tables of these models have both items, and so
# does the firmware a buyer gets today: the rows are taken from the donor page.
_P_NEWER_ROWS = ("Startup Configuration", "Backup Ready")
BORROWED_ROWS = {
    "ph42-020-s300-r": ("ph54-100-s500-r", _P_NEWER_ROWS),
    "pm54-040-s250-r": ("pm42-010-s260-r", _P_NEWER_ROWS),
    "pm54-060-s250-r": ("pm42-010-s260-r", _P_NEWER_ROWS),
}
BORROWED_ROW_NOTE = ("row: not on this page, an older stored revision of it; taken from control-tables/{donor}.md, "
                     "a newer page of the same DYNAMIXEL-P table (DynamixelSDK's tables have the item too); the "
                     "rest of the page, Drive Mode's 0 ~ 1 included, is kept as this revision prints it")

# ---------------------------------------------------------------------------------------------
# Signedness
# ---------------------------------------------------------------------------------------------

# The 2.0 families report these R items in two's complement although the pages print no range.
SIGNED_READBACK_FAMILIES = P2_FAMILIES
SIGNED_READBACK = {"present_pwm", "present_current", "present_velocity", "present_position",
                   "present_load", "velocity_trajectory", "position_trajectory"}

# Families whose device writes -1 into Bus Watchdog on a timeout (Bus Watchdog include).
BUS_WATCHDOG_FAMILIES = {"x", "mx2", "p", "y"}

# Model notes on signedness: (families, note).
SIGNED_MODEL_NOTES = [
    (P2_FAMILIES, "signed: Present PWM/Current/Load/Velocity/Position and Velocity/Position Trajectory print no "
                  "range but are two's-complement values on Protocol 2.0 devices (README behaviour 20); they are "
                  "marked signed"),
    (V1_FAMILIES | {"xl320"}, "signed: Present Speed / Present Load (and Moving Speed, Goal Torque) encode the "
                              "direction in bit 10 (0 ~ 2,047), so they stay unsigned"),
]

# ---------------------------------------------------------------------------------------------
# Accepted values
# ---------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class OpmodeBlock:
    """An Operating Mode block a page may show, and the include whose Value table lists the modes."""
    markers: tuple         # any of these in the page text selects the block
    include: str
    note: str = ""         # "" for the usual "values: the modes listed in <include>.md ..."
    without_item: str = ""  # the note's reasoning needs the model to have no such item


# The first block the page shows wins (pages that print the list themselves, P and PRO, skip this).
OPMODE_BLOCKS = [
    OpmodeBlock(("ControlTableOpmodeSix2", "control_table_opmode_six_2.md"), "control_table_opmode_six_2"),
    OpmodeBlock(("ControlTableMxOpmode2", "control_table_mx_opmode_2.md"), "control_table_mx_opmode_2"),
    OpmodeBlock(("<OperatingModeXl />",), "control_table_mx_opmode_2",
                note="values: the page's <OperatingModeXl /> block is not in the reference; this model has no "
                     "Goal Current item (no current sensing), so the four non-current modes of "
                     "control_table_mx_opmode_2.md are used: 1, 3, 4, 16",
                without_item="goal_current"),
]

# Operating Mode values per family whose Operating Mode block is not in the reference: the modes
# that block lists, and the note.
OPMODE_VALUES = {
    "y": ([0, 1, 3], "range: the table prints 0 ~ 3; values: the DYNAMIXEL-Y Operating Mode block "
                     f"({EMANUAL_INCLUDES}y/control_table_33_operating_mode.md, not in the reference) lists three "
                     "modes: 0 Current Control Mode, 1 Velocity Control Mode, 3 (Default) Position Control Mode; "
                     "2 selects none and is refused"),
}

# Protocol Type values per variant: the include whose Value table lists them, the note ({values}
# is the list), and the product group whose Liquid branch is read ("" for the page's own).
PROTOCOL_TYPE_BLOCKS = {
    "x330": ("control_table_protocolversion",
             "values: the table prints 2 ~ 22; the accepted values are those of the XL330/XC330 Protocol Type "
             "block (control_table_protocolversion.md): {values}", ""),
    "xm335-t323": ("control_table_protocolversion",
                   "values: the table prints 2 ~ 22, as on XL330/XC330, but the Protocol Type block has no "
                   "branch for the xm335 group (its default branch lists the X430 values 1, 2); the XL330/XC330 "
                   "branch is used, whose values the printed range spans: {values}", "xc330"),
}

# Baud Rate values per family where the table's range names indices that select no rate.
BAUD_RATE_VALUES = {
    "pro": ([i for i, _ in EXTERNAL_BAUD["pro"][0]],
            f"values: the table prints 0 ~ 13 but the PRO Baud Rate include ({EXTERNAL_BAUD['pro'][1]}) defines "
            "only 0 ~ 8; values 9 ~ 13 select no bit rate, so only 0 ~ 8 are accepted"),
}

# ---------------------------------------------------------------------------------------------
# Bounds and widened ranges
# ---------------------------------------------------------------------------------------------

# Families where CW/CCW Angle Limit bound Goal Position in joint mode only, and the other modes
# besides wheel mode where they do not apply.
ANGLE_LIMIT_FAMILIES = {"ax": "", "rx": "", "ex": "", "xl320": "", "mx1": ", or multi-turn mode (both 4,095)"}

# Bounds the tables do not print, per family: (item, bounding item for limit_max, note). The
# static max becomes the lower of the two.
LIMIT_MAX_OVERRIDES = {
    "mx2": [("profile_acceleration", "acceleration_limit",
             "limit_max: acceleration_limit: 'Profile Acceleration(108) can't be configured with any values "
             f"exceeding Acceleration Limit(40)' ({EMANUAL_INCLUDES}control_table_acclimit.md, not in the "
             "reference)")],
}

# Items whose printed range excludes their factory value: the max accepted instead, and the note
# ({min} ~ {max} is the printed range, {initial} the factory value).
WIDEN_TO_FACTORY = {
    "secondary_id": (255, "range: {min} ~ {max} is printed but the factory value is {initial}; the Secondary "
                          "ID include says '0 ~ 252 Activate Secondary ID function, 253 ~ 255 Deactivate "
                          f"Secondary ID function, Default value 255' ({EMANUAL_INCLUDES}control_table_shadowid.md, "
                          "not in the reference), so 0 ~ 255 is accepted"),
}

# The same widening where a family's own block says it: key -> (max, note) by family.
WIDEN_TO_FACTORY_BY_FAMILY = {
    "y": {"secondary_id": (255, "range: {min} ~ {max} is printed but the factory value is {initial}; the DYNAMIXEL-Y "
                                "Secondary ID block's Value table says '0 ~ 252 Enable Secondary ID function', "
                                "'253 ~ 255 Disable Secondary ID function, Default value : 255' "
                                f"({EMANUAL_INCLUDES}y/control_table_10_secondary_id.md, not in the reference), so "
                                "0 ~ 255 is accepted")},
}

# ---------------------------------------------------------------------------------------------
# Range donors
# ---------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class RangeDonors:
    """Pages whose tables print the ranges a family's pages leave out: both describe the items with
    the same include blocks."""
    label: str       # how the note names the borrowing family's pages
    pages: tuple     # the donor pages (converted ones), in the order they are asked


RANGE_DONORS = {"mx2": RangeDonors("MX(2.0)", ("xm430-w350", "xl430-w250")),
                # 'the similar control table structure to DYNAMIXEL-PRO series' (its page header)
                "rh-p12-rn": RangeDonors("RH-P12-RN", ("h54-200-s500-r",))}

# Names that differ between a page and its donor page.
NAME_ALIASES = {"protocol version": "protocol type"}
