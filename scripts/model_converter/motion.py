"""The motion block of a model: degrees per pulse, the velocity, current and acceleration units,
the motor figures (the page's Specifications table, else motor_specs.py), and what the live
readings show at rest (rest_values.py): the current reading's zero and the supply voltage."""

from __future__ import annotations

import re

from .decisions.model_fields import DEGREES_PER_PULSE, VELOCITY_UNITS
from .decisions.motor_specs import EXTERNAL_SPECS
from .decisions.rest_values import CURRENT_ZEROS, DEFAULT_VOLTAGE_UNIT_V, SUPPLY_NOTE, SUPPLY_SPREAD
from .items import Draft
from .markdown import clean_cell, tables_in, unit_number
from .spec_table import parse_spec_table


def motion(d: Draft) -> dict:
    """The model's motion block."""
    dpp, note = d.lookup(DEGREES_PER_PULSE)
    d.notes.append(note)
    m = {"degrees_per_pulse": dpp, "velocity_unit_rpm": velocity_unit(d)}
    cur = current_unit(d)
    if cur is not None:
        m["current_unit_ma"] = cur
    specs(d, m)
    acceleration_unit(d, m)
    current_zero(d, m)
    rest_supply(d, m)
    return m


def velocity_unit(d: Draft) -> float:
    """rev/min per velocity unit, from models.tsv (else VELOCITY_UNITS), checked against the Unit column."""
    decided = d.lookup(VELOCITY_UNITS, None)
    if decided is not None:
        d.notes.append(decided[1])
        return decided[0]
    col = d.tsv["max_speed_units"]
    mt = re.search(r"x ([\d.]+) rev/min|about ([\d.]+) ?rpm/unit", col)
    if not mt:
        raise ValueError(f"{d.name}: no velocity unit in models.tsv")
    v = float(mt.group(1) or mt.group(2))
    for key in ("velocity_limit", "goal_velocity", "profile_velocity"):
        item = d.by_key.get(key)
        if item and item.unit and unit_number(item.unit) not in (None, v):
            raise ValueError(f"{d.name}: velocity unit {item.unit} disagrees with models.tsv {v}")
    d.notes.append(f"motion.velocity_unit_rpm: {v} rev/min per unit (models.tsv '{col.strip()}')")
    return v


def current_unit(d: Draft) -> float | None:
    """mA per current unit: a Unit column in mA, else a figure the description states; None without one."""
    for key in ("current_limit", "goal_current", "present_current", "goal_torque", "torque_limit"):
        item = d.by_key.get(key)
        if item and item.unit and "mA" in item.unit:
            u = unit_number(item.unit)
            d.notes.append(f"motion.current_unit_ma: {u} (Unit column of {item.row.name}: '{item.unit}')")
            return u
        if item and item.unit and re.fullmatch(r"[\d.]+\s*\[A\]", item.unit):
            u = round(unit_number(item.unit) * 1000, 6)
            d.notes.append(f"motion.current_unit_ma: {u:g} (Unit column of {item.row.name}: '{item.unit}')")
            return u
    text = d.page.text
    for pat, what in ((r"\|\s*(?i:about)\s+([\d.]+)\s*\[?mA\]?", "the Current Limit description table"),
                      (r"I = \( ([\d.]+)mA \)", "the Current(68) description 'I = ( 4.5mA ) * (CURRENT - 2048)'"),
                      (r"the unit is (\d+)mA", "the Sensed Current(56) description")):
        mt = re.search(pat, text)
        if mt:
            u = float(mt.group(1))
            d.notes.append(f"motion.current_unit_ma: {u} ({what})")
            return u
    return None


def specs(d: Draft, m: dict):
    """no_load_speed_rpm / stall_torque_nm / stall_current_a / nominal_voltage_v from the page's
    Specifications table, else EXTERNAL_SPECS."""
    fields = "motion.no_load_speed_rpm / stall_torque_nm / stall_current_a / nominal_voltage_v"
    page_spec = parse_spec_table(d.page.lines)
    if page_spec:
        ps = page_spec
        m["no_load_speed_rpm"], m["stall_torque_nm"] = ps.rpm, ps.nm
        if ps.amps is not None:
            m["stall_current_a"] = ps.amps
        if ps.volts is not None:
            m["nominal_voltage_v"] = float(ps.volts)
        amps = f", {ps.amps} A" if ps.amps is not None else ""
        d.notes.append(f"{fields}: {ps.rpm} rev/min, {ps.nm} N.m{amps} at {ps.volts} V from this page's "
                       f"Specifications table (control-tables/{d.name}.md: Stall Torque "
                       f"'{ps.torque_text}', No Load Speed '{ps.speed_text}'){ps.detail}")
        if ps.amps is None:
            d.notes.append("motion.stall_current_a omitted: the page's Stall Torque row states no current")
        return
    spec = EXTERNAL_SPECS.get(d.name)
    if spec is None:
        d.notes.append("motion: no_load_speed_rpm, stall_torque_nm, stall_current_a and nominal_voltage_v "
                       "omitted: the specification section is not in the reference and no stated figure "
                       "was found")
        return
    stated, keys = [], []
    for key, value, unit in (("no_load_speed_rpm", spec.rpm, "rev/min"), ("stall_torque_nm", spec.nm, "N.m"),
                             ("stall_current_a", spec.amps, "A")):
        if value is not None:
            m[key] = value
            stated.append(f"{value} {unit}")
            keys.append(key)
    m["nominal_voltage_v"] = float(spec.volts)
    figures = f"{', '.join(stated)} at {spec.volts} V" if stated else f"{spec.volts} V"
    d.notes.append(f"motion.{' / '.join(keys + ['nominal_voltage_v'])}: {figures} "
                   f"from the e-Manual specifications: {spec.source}")
    if spec.missing:
        d.notes.append(f"motion: {spec.missing}")


def acceleration_unit(d: Draft, m: dict):
    """acceleration_unit_rpm2: rev/min^2 per unit of Profile Acceleration, from its Unit column or,
    on pages without one (MX(2.0)), the Unit row of its description section."""
    item = d.by_key.get("profile_acceleration")
    if item is None:
        other = d.by_key.get("goal_acceleration")
        extra = (f" (its Goal Acceleration({other.row.address}) is a different item, in '{other.unit}')"
                 if other is not None and other.unit else "")
        d.notes.append(f"motion.acceleration_unit_rpm2 omitted: the model has no Profile Acceleration "
                       f"item{extra}")
        return
    accel = re.compile(r"([\d.,]+)\s*\[rev/min(?:²|2|\^2)\]")
    if item.unit:
        first = item.unit.split(" / ")[0]
        mt = accel.fullmatch(first.strip())
        if not mt:
            d.notes.append(f"motion.acceleration_unit_rpm2 omitted: the Unit column of Profile Acceleration "
                           f"('{item.unit}') is not in rev/min²")
            return
        m["acceleration_unit_rpm2"] = float(mt.group(1).replace(",", ""))
        d.notes.append(f"motion.acceleration_unit_rpm2: {m['acceleration_unit_rpm2']} rev/min² per unit "
                       f"(Unit column of Profile Acceleration({item.row.address}): '{item.unit}'"
                       + (", velocity-based profile" if " / " in item.unit else "") + ")")
        return
    for sec in d.page.section_for(item.row.address):
        for tab in tables_in(d.page.section_text(sec, d.ref).splitlines()):
            for cells in tab.rows:
                if len(cells) >= 2 and clean_cell(cells[0]).lower() == "unit":
                    mt = accel.fullmatch(clean_cell(cells[1]))
                    if mt:
                        m["acceleration_unit_rpm2"] = float(mt.group(1).replace(",", ""))
                        d.notes.append(
                            f"motion.acceleration_unit_rpm2: {m['acceleration_unit_rpm2']} rev/min² per unit "
                            f"(the page's table has no Unit column; the '{tab.header[0]}' table of the Profile "
                            f"Acceleration({item.row.address}) description (control_table_profile_acceleration "
                            f"include) says 'Unit {clean_cell(cells[1])}')")
                        return
    d.notes.append("motion.acceleration_unit_rpm2 omitted: no rev/min² unit is stated for Profile "
                   "Acceleration")


def current_zero(d: Draft, m: dict):
    """current_zero: the value of an offset current reading at 0 A (CURRENT_ZEROS), which is also
    its power-on value (the servo is at rest)."""
    for rule in CURRENT_ZEROS:
        item = d.by_key.get(rule.key)
        if item is None:
            continue
        mt = re.search(rule.pattern, d.page.text)
        if not mt:
            raise ValueError(f"{d.name}: {rule.key} is offset but the page does not state its zero")
        zero = int(mt.group(1).replace(",", ""))
        m["current_zero"] = zero
        d.notes.append(f"motion.current_zero: {zero}, the {item.row.name}({item.row.address}) reading at 0 A "
                       f"({rule.source})")
        if item.initial != zero:
            item.notes.append(f"initial: the page shows {item.initial}; {zero} chosen, the value at rest "
                              f"({rule.source}), which a servo powered on at rest reads")
            item.initial = zero
        return


def rest_supply(d: Draft, m: dict):
    """The power-on Present (Input) Voltage, which is the supply: the midpoint of the factory limits
    chosen by item_rules, unless that is further than SUPPLY_SPREAD from the nominal voltage."""
    item = d.by_key.get("present_input_voltage") or d.by_key.get("present_voltage")
    nominal = m.get("nominal_voltage_v")
    chosen = [n for n in (item.notes if item else []) if n.startswith("initial:") and "midpoint" in n]
    if item is None or nominal is None or not chosen:
        return
    unit = unit_number(item.unit) or DEFAULT_VOLTAGE_UNIT_V
    share = abs(item.initial * unit - nominal) / nominal
    if share <= SUPPLY_SPREAD:
        return
    midpoint = f"{item.initial * unit:g} V"
    item.initial = round(nominal / unit)
    item.notes[item.notes.index(chosen[0])] = SUPPLY_NOTE.format(value=item.initial, volts=f"{nominal:g}",
                                                                 midpoint=midpoint, share=share)
