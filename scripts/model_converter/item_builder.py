"""The items of one page: keys, access, ranges (item_ranges.py), signedness, the accepted values
of Operating Mode, Protocol Type and Baud Rate, and the power-on values the pages print as '-'.

build_items runs the passes in their order; each pass reads what the earlier ones decided.
"""

from __future__ import annotations

import re

from . import item_ranges
from .catalogue import P2_FAMILIES, V1_FAMILIES, X330
from .decisions import EXTERNAL_BAUD, SIGNED_READBACK, ZERO_REASONS
from .items import Draft, Item
from .markdown import clean_cell, clean_unit, parse_int, snake_key, tables_in
from .page import Row


def build_items(d: Draft, fw: int) -> None:
    """All passes over the items of `d`; `fw` is the model's firmware_version."""
    make_items(d)
    item_ranges.printed_ranges(d)
    item_ranges.fill_unprinted_ranges(d)
    signedness(d)
    operating_modes(d)
    protocol_type_values(d)
    baud_rate_values(d)
    item_ranges.resolve_limits(d)
    initial_values(d, fw)
    item_ranges.secondary_id_range(d)
    angle_limit_note(d)
    item_ranges.mx2_profile_limit(d)
    item_ranges.check_description_agreement(d)


def make_items(d: Draft):
    keys_seen: dict[str, Row] = {}
    for row in d.page.rows:
        key = snake_key(row.name)
        item = Item(row, key)
        if key in keys_seen:
            item.key = f"{key}_{row.address}"
            item.notes.append(f"key: '{key}' is also the key of {keys_seen[key].name}({keys_seen[key].address}); "
                              f"disambiguated with the address")
        keys_seen[key] = row
        if row.access == "R/RW":
            item.notes.append("access: the page prints 'R/RW' (read-only or writable depending on "
                              "External Port Mode); RW is used and the mode check is left to the emulator")
        unit = clean_unit(row.unit)
        item.unit = unit
        d.add(item)


def page_has_extended_mode(d: Draft) -> bool:
    """True when the model's Operating Mode accepts 4 (Extended Position Control Mode)."""
    mode = next((i for i in d.items if i.key == "operating_mode"), None)
    return mode is not None and (4 in (mode.values or []) or
                                 (mode.max is not None and mode.max >= 4))


def signedness(d: Draft):
    for item in d.items:
        if (item.min is not None and item.min < 0) or (item.values and min(item.values) < 0):
            item.signed = True
        if item.limit_min and item.limit_min.startswith("-"):
            item.signed = True
        if d.family in P2_FAMILIES and item.key in SIGNED_READBACK and not item.signed:
            item.signed = True
            item.notes.append("signed: the page prints no range, but the device reports this value in "
                              "two's complement (negative for reverse direction / below zero)")
        if (item.key == "goal_position" and d.family in P2_FAMILIES and not item.signed
                and page_has_extended_mode(d)):
            item.signed = True
            item.notes.append("signed: Extended Position Control Mode (Operating Mode 4) takes goals of "
                              "-256 ~ 256 rev in two's complement (opmode include); the range rule of the "
                              "motion model widens the static range in that mode")
        if item.key == "bus_watchdog" and d.family in ("x", "mx2", "p"):
            item.signed = True
            printed = f"{item.min} ~ {item.max}"
            why = ""
            if item.min and item.min > 0:
                item.min = 0
                why = (f"range: {printed} is printed for the active values; 0 (deactivate, clear the "
                       f"watchdog error) is accepted too, per the Bus Watchdog include's Values table; ")
            item.notes.append(f"{why}signed: the device itself sets -1 (0xFF) on a watchdog timeout (Bus "
                              f"Watchdog include), so the item is signed; writes accept {item.min} ~ {item.max}")
    if d.family in P2_FAMILIES:
        d.notes.append("signed: Present PWM/Current/Load/Velocity/Position and Velocity/Position Trajectory "
                       "print no range but are two's-complement values on Protocol 2.0 devices "
                       "(README behaviour 20); they are marked signed")
    if d.family in V1_FAMILIES or d.family == "xl320":
        d.notes.append("signed: Present Speed / Present Load (and Moving Speed, Goal Torque) encode the "
                       "direction in bit 10 (0 ~ 2,047), so they stay unsigned")


def operating_modes(d: Draft):
    item = d.by_key.get("operating_mode")
    if item is None:
        return
    if item.values is not None:          # P / PRO print the list
        return
    text = d.page.text
    tags = [("OpmodeSix2", "opmode_six_2", "control_table_opmode_six_2"),
            ("MxOpmode2", "mx_opmode_2", "control_table_mx_opmode_2")]
    for tag, inc_name, file in tags:
        if f"ControlTable{tag}" in text or f"control_table_{inc_name}.md" in text:
            item.values = mode_values(d, file)
            item.notes.append(f"values: the modes listed in {file}.md (the page's Operating Mode block)")
            return
    if "<OperatingModeXl />" in text:
        assert "goal_current" not in d.by_key
        item.values = mode_values(d, "control_table_mx_opmode_2")
        item.notes.append("values: the page's <OperatingModeXl /> block is not in the reference; this model "
                          "has no Goal Current item (no current sensing), so the four non-current modes "
                          "of control_table_mx_opmode_2.md are used: 1, 3, 4, 16")
        return
    raise ValueError(f"{d.name}: no Operating Mode block recognised")


def mode_values(d: Draft, include: str) -> list[int]:
    text = d.ref.include(include, d.page.group)
    values = []
    for tab in tables_in(text.splitlines()):
        if tab.header and tab.header[0].lower() == "value":
            for cells in tab.rows:
                n = re.match(r"\s*(\d+)", clean_cell(cells[0]))
                if n:
                    values.append(int(n.group(1)))
            break
    if not values:
        raise ValueError(f"no mode table in {include}")
    return values


def protocol_type_values(d: Draft):
    item = d.by_key.get("protocol_type")
    if item is None or d.name not in X330:
        return
    text = d.ref.include("control_table_protocolversion", d.page.group)
    tab = next(t for t in tables_in(text.splitlines()) if t.header[0].lower() == "value")
    item.values = [int(re.match(r"\s*(\d+)", clean_cell(c[0])).group(1)) for c in tab.rows]
    item.notes.append(f"values: the table prints 2 ~ 22; the accepted values are those of the XL330/XC330 "
                      f"Protocol Type block (control_table_protocolversion.md): "
                      f"{', '.join(map(str, item.values))}")


def baud_rate_values(d: Draft):
    """PRO prints 0 ~ 13 but its baud include lists only 0 ~ 8."""
    item = d.by_key.get("baud_rate")
    if d.family == "pro":
        item.values = [i for i, _ in EXTERNAL_BAUD["pro"][0]]
        item.notes.append("values: the table prints 0 ~ 13 but the PRO Baud Rate include "
                          f"({EXTERNAL_BAUD['pro'][1]}) defines only 0 ~ 8; values 9 ~ 13 select no bit "
                          "rate, so only 0 ~ 8 are accepted")


def initial_values(d: Draft, fw: int):
    mid_position = {"x": 2048, "mx2": 2048, "mx1": 2048, "ex": 2048, "ax": 512, "rx": 512,
                    "xl320": 512, "p": 0, "pro": 0}[d.family]
    vmin = d.by_key.get("min_voltage_limit")
    vmax = d.by_key.get("max_voltage_limit")
    for item in d.items:
        text = item.row.initial
        n = parse_int(text)
        if n is not None:
            item.initial = n
            continue
        key = item.key
        if key == "firmware_version":
            item.initial = fw
            item.notes.append(f"initial: the page shows '-'; the model's firmware_version ({fw})")
        elif key == "id" and re.fullmatch(r"1,\s*2", text):
            item.initial = 1
            item.notes.append("initial: the page shows '1, 2' (axis 1 and axis 2 of the dual-axis module); "
                              "1 is stored here and the emulator gives the second axis ID 2")
        elif key == "model_information":
            item.initial = 0
            item.notes.append("initial: the page shows '-' and does not describe the contents; 0 chosen")
        elif key in ("torque_limit",) and (text.lower() == "max torque" or text == "-"):
            item.initial_from = "max_torque"
            what = "'Max Torque'" if text != "-" else "'-'"
            item.notes.append(f"initial: the page shows {what}; Torque Limit takes the value of Max Torque at "
                              f"power-on (Torque Limit description: 'the value of Max Torque ... is used as "
                              f"the initial value')")
        elif key == "goal_pwm":
            item.initial_from = "pwm_limit"
            item.notes.append("initial: the page shows '-'; Goal PWM starts at PWM Limit (the X/MX(2.0) Goal "
                              "PWM block's range row reads 'Initial Value of PWM Limit', and switching Operating "
                              "Mode resets Goal PWM to PWM Limit)")
        elif key == "goal_current":
            item.initial_from = "current_limit"
            item.notes.append("initial: the page shows '-'; Goal Current starts at Current Limit (switching "
                              "Operating Mode resets Goal Current to Current Limit, opmode block)")
        elif key in ("goal_position", "present_position", "position_trajectory"):
            item.initial = mid_position
            item.notes.append(f"initial: the page shows '-' (the position at power-on is not known to the "
                              f"table); {mid_position} (mid-range / centre of travel) chosen, inside the "
                              f"range and the position limits")
        elif key in ("present_input_voltage", "present_voltage") and vmin and vmax:
            v = (vmin.initial + vmax.initial) // 2
            item.initial = v
            item.notes.append(f"initial: the page shows '-'; {v} (midpoint of the factory Min/Max Voltage "
                              f"Limit {vmin.initial} ~ {vmax.initial}) chosen as a plausible supply voltage")
        elif key == "present_temperature":
            item.initial = 25
            item.notes.append("initial: the page shows '-'; 25 (room temperature, deg C) chosen")
        elif key == "acceleration_limit":
            item.initial = item.static_range()[1]
            item.notes.append(f"initial: the page shows '-'; {item.initial:,} (the top of the range, so the "
                              f"factory setting refuses no Goal Acceleration) chosen")
        elif key == "sensed_current":
            item.initial = 512
            item.notes.append("initial: the page shows '-'; 512 ('512 is equal to 0mA', description) chosen")
        else:
            item.initial = 0
            what = "'-'" if text in ("-", "") else f"'{text}'"
            reason = next((r for pat, r in ZERO_REASONS if re.fullmatch(pat, key)), None)
            if reason is None:
                raise ValueError(f"{d.name}.{key}: initial {what} and no rule for it")
            item.notes.append(f"initial: the page shows {what}; 0 chosen ({reason})")


def angle_limit_note(d: Draft):
    """AX/RX/EX/MX 1.0 and XL-320: CW/CCW Angle Limit bound Goal Position only in joint mode."""
    if d.family not in V1_FAMILIES and d.family != "xl320":
        return
    item = d.by_key["goal_position"]
    multi = ", or multi-turn mode (both 4,095)" if d.family == "mx1" else ""
    item.notes.append("limits: CW/CCW Angle Limit(6, 8) bound Goal Position in joint mode only, and a goal "
                      "outside them raises the Angle Limit Error bit rather than a range error; they do not "
                      f"apply in wheel mode (both 0){multi}. limit_min/limit_max cannot express a "
                      "mode-dependent bound, so none is set and the family code applies the rule (README 32)")
