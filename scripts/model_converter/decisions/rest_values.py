"""What a servo's live readings show at rest, where a page states it or the power-on value chosen
for an item would put a resting servo where no real one is: the value of a current reading at 0 A,
and the supply a servo is powered at. Each entry carries the evidence quoted in its note."""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class CurrentZero:
    """A current reading whose 0 A is not 0: the item, the page's sentence stating the zero (a
    regex whose group 1 is the value) and how the note names that sentence."""
    key: str
    pattern: str
    source: str


# The current readings of the Protocol 1.0 pages are offset, unsigned values. A model with the
# item whose page lacks the sentence is refused (the converter cannot guess the zero).
CURRENT_ZEROS = [
    CurrentZero("current", r"At an idle state without current flow, this value is ([\d,]+)",
                "the Current(68) description: 'At an idle state without current flow, this value is "
                "2,048(0x800)', and 'I = ( 4.5mA ) * (CURRENT - 2048 )'"),
    CurrentZero("sensed_current", r"([\d,]+) is equal to 0mA",
                "the Sensed Current(56) description: '512 is equal to 0mA, and it means there is no "
                "torque from the motor'"),
]

# The Present (Input) Voltage at power-on is the supply the emulated servo runs on. The midpoint
# of the factory voltage limits (item_rules._SUPPLY_VOLTAGE) is kept where it is within this share
# of the nominal voltage; further away it is a supply the servo is not specified for, and the
# nominal voltage is used. The e-Manual's Input Voltage ranges reach about 20 % either side of the
# recommended voltage: AX 9.0 ~ 12.0 V around 11.1 V (ax-12a.md), MX 10.0 ~ 14.8 V around 12.0 V
# (mx-64.md), RX-28/RX-64 and EX-106+ 12 ~ 18.5 V around 14.8 V (rx-28.md, ex-106+.md), XL-320
# 6 ~ 8.4 V around 7.4 V (xl-320.md).
SUPPLY_SPREAD = 0.2
SUPPLY_NOTE = ("initial: the page shows '-'; {value} ({volts} V, motion.nominal_voltage_v) chosen as the supply: "
               "the midpoint of the factory Min/Max Voltage Limit ({midpoint}) is {share:.0%} away from the "
               "nominal voltage, further than the e-Manual's Input Voltage ranges reach (about 20 % either side "
               "of the recommended voltage: MX '10.0 ~ 14.8 [V] (Recommended : 12.0 [V])', AX '9.0 ~ 12.0 [V] "
               "(Recommended : 11.1V)', RX-28 '12 ~ 18.5V (Recommended : 14.8V)')")
# The unit of the voltage items where the page's table has no Unit column.
DEFAULT_VOLTAGE_UNIT_V = 0.1
