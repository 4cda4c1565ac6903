#!/usr/bin/env python3
"""Convert the offline ROBOTIS e-Manual control-table pages into dxlemu model files.

Usage:
    python3 scripts/convert_models.py [--reference DIR] [--out DIR] [--check] [--quiet]

Reads the pages of CONVERTED_PAGES in DIR/control-tables/*.md (default DIR: ../shared/reference
relative to the repository root), the shared description blocks in DIR/control-tables/includes/
and DIR/models.tsv, and writes OUT/<name>.json for each plus OUT/catalog.json (default OUT:
models/). Nothing else is written; the pages it does not convert yet are named. The format is docs/model-format.md; the JSON Schema is
models/schema/model.schema.json.

--check regenerates everything in memory and exits 1, naming the files that differ from what is
on disk (missing, changed or stale), without writing anything. CI uses it.

Everything the pages do not state is a decision taken here; each one is written into the model's
`notes` (model level) or the item's `note`, so a reviewer can read the JSON and see why. Facts
that come from outside the offline reference (a few e-Manual includes that were not copied, motor
specifications, the boot time) carry the public URL they were read from.

Standard library only.
"""

from __future__ import annotations

import argparse
import html
import json
import re
import sys
from dataclasses import dataclass, field
from fractions import Fraction
from pathlib import Path

REPO_ROOT = Path(__file__).resolve().parent.parent
DEFAULT_REFERENCE = REPO_ROOT.parent / "shared" / "reference"
DEFAULT_OUT = REPO_ROOT / "models"

EMANUAL_INCLUDES = "https://github.com/ROBOTIS-GIT/emanual/blob/master/_includes/en/dxl/"

# ---------------------------------------------------------------------------------------------
# Families
# ---------------------------------------------------------------------------------------------

V1_FAMILIES = {"ax", "rx", "ex", "mx1"}           # Protocol 1.0 control tables
P2_FAMILIES = {"x", "mx2", "p", "pro"}            # Protocol 2.0 tables with 4-byte items
X330 = {"xl330-m288", "xl330-m077", "xc330-t288"}  # product groups xl330 / xc330


# The pages whose layouts this converter reads. The reference holds more (the rest of the ROBOTIS
# catalogue); they are named by --check and the summary as not converted, and are not models yet.
CONVERTED_PAGES = (
    "2xl430-w250",
    "ax-12a",
    "ax-12w",
    "ax-18a",
    "ex-106+",
    "h54-200-s500-r",
    "mx-106",
    "mx-106-2",
    "mx-28",
    "mx-28-2",
    "mx-64",
    "mx-64-2",
    "ph54-200-s500-r",
    "rx-24f",
    "rx-28",
    "rx-64",
    "xc330-t288",
    "xc430-w150",
    "xc430-w240",
    "xh430-w210",
    "xh430-w350",
    "xh540-w150",
    "xh540-w270",
    "xl-320",
    "xl330-m077",
    "xl330-m288",
    "xl430-w250",
    "xm430-w210",
    "xm430-w350",
    "xm540-w150",
    "xm540-w270",
    "xw540-t260",
)


def family_of(name: str) -> str:
    """Behaviour family from the page file name (docs/model-format.md `family`)."""
    if name == "xl-320":
        return "xl320"
    if name.startswith(("x", "2x")):
        return "x"
    if name.startswith("mx-"):
        return "mx2" if name.endswith("-2") else "mx1"
    if name.startswith("ax-"):
        return "ax"
    if name.startswith("rx-"):
        return "rx"
    if name.startswith("ex-"):
        return "ex"
    if name.startswith("ph"):
        return "p"
    if name.startswith("h54"):
        return "pro"
    raise SystemExit(f"convert_models: no family rule for page {name!r}")


def product_group(name: str, family: str) -> str:
    """The e-Manual `page.product_group`, used to pick Liquid branches of the includes."""
    if name.startswith("xl330"):
        return "xl330"
    if name.startswith("xc330"):
        return "xc330"
    return {"x": "dxl_x430", "mx2": "dxl_mx2", "mx1": "dxl_mx", "ax": "dxl_ax", "rx": "dxl_rx",
            "ex": "dxl_ex", "xl320": "dxl_xl320", "p": "dxl_p", "pro": "dxl_pro"}[family]


# ---------------------------------------------------------------------------------------------
# Model-level decisions (each is explained in the notes written with it)
# ---------------------------------------------------------------------------------------------

# Firmware Version: the pages print "-". Lowest version that has every instruction and item the
# page shows, per ../protocol2.md, ../protocol1.md and the includes.
FIRMWARE = {
    "x": (45, "firmware_version: the page shows '-'; 45 is the lowest X430/540 firmware with every "
              "feature the table and protocol2.md describe: Fast Sync Read / Fast Bulk Read (X430/540 "
              "fw v45+), Startup Configuration(60) ('available from firmware V45'), the broadcast "
              "Factory Reset 0xFF guard (fw 42+), time-based profiles (fw 42+), Bus Watchdog (v38+)"),
    "x330": (46, "firmware_version: the page shows '-'; 46 is the lowest X330 firmware with Fast Sync "
                 "Read / Fast Bulk Read (protocol2.md: X330 fw v46+), which also covers the Factory "
                 "Reset broadcast guard (fw 42+) and Startup Configuration(60)"),
    "mx2": (42, "firmware_version: the page shows '-'; 42 covers the broadcast Factory Reset 0xFF guard "
                "(protocol2.md: 'MX(2.0) FW42') and time-based profiles (fw 42); Fast Sync/Bulk Read "
                "are not supported on MX(2.0) at any version"),
    "mx1": (40, "firmware_version: the page shows '-'; 40 is the first MX Protocol 1.0 firmware with "
                "the Reboot instruction (protocol1.md: 'MX-28/64/106(V40)') and Realtime Tick(50) "
                "('available from Firmware v40')"),
    "p": (12, "firmware_version: the page shows '-'; 12 is the lowest P-series firmware with Fast Sync "
              "Read / Fast Bulk Read (protocol2.md: 'P Series(Fw v12 or above)')"),
    "pro": (1, "firmware_version: the page shows '-'; no instruction or item of the legacy PRO table "
               "depends on a firmware version in the reference, so 1 is an arbitrary placeholder"),
    "xl320": (1, "firmware_version: the page shows '-'; nothing in the reference depends on the XL-320 "
                 "firmware version, so 1 is an arbitrary placeholder"),
    "ax": (1, "firmware_version: the page shows '-'; nothing in the reference depends on the AX "
              "firmware version, so 1 is an arbitrary placeholder"),
    "rx": (1, "firmware_version: the page shows '-'; nothing in the reference depends on the RX "
              "firmware version, so 1 is an arbitrary placeholder"),
    "ex": (1, "firmware_version: the page shows '-'; nothing in the reference depends on the EX "
              "firmware version, so 1 is an arbitrary placeholder"),
}

TIMING_V1 = {"ping_us": 18, "read_us": 22, "write_us": 24, "write_per_byte_us": 6}
TIMING_OTHER = {"ping_us": 50, "read_us": 50, "write_us": 50, "write_per_byte_us": 0}
BOOT_MS = 400
BOOT_URL = "https://github.com/ROBOTIS-GIT/emanual/issues/1698"
BOOT_NOTE = (f"timing.boot_ms: {BOOT_MS} ms. The e-Manual gives no figure; the only stated one found is "
             f"ROBOTIS-GIT/emanual issue #1698 ({BOOT_URL}): XC330 servos answer the Reboot instruction "
             "at once, then 'refuse to reply for about 0.4 seconds while rebooting' (the maintainers "
             "declined to document it). No per-model figure exists, so 400 ms is used for every model "
             "(Dynamixel2Arduino waits up to 3 s, an upper bound rather than a measurement)")

# Baud tables that are not in the offline reference (P and PRO includes were not copied).
EXTERNAL_BAUD = {
    "p": ([(0, 9600), (1, 57600), (2, 115200), (3, 1000000), (4, 2000000), (5, 3000000),
           (6, 4000000), (7, 4500000), (8, 6000000), (9, 10500000)],
          EMANUAL_INCLUDES + "p/control_table_8_baud_rate.md"),
    "pro": ([(0, 9600), (1, 57600), (2, 115200), (3, 1000000), (4, 2000000), (5, 3000000),
             (6, 4000000), (7, 4500000), (8, 10500000)],
            EMANUAL_INCLUDES + "control_table_8_baudrate_pro.md"),
}

# Motor specifications read from public e-Manual sources (the offline copies omit most
# specification sections), for models whose page has no Specifications table. Figures at the
# voltage named (the recommended input voltage unless the source says otherwise); None where the
# source states no such figure, and `missing` then says why. Models not listed and without a
# specification table on their page get no no_load_speed_rpm / stall_torque_nm / stall_current_a.
#
# Where an English page could not be read, the figures come from the e-Manual's own data files:
# `_data/dxl_x_info.yml` / `_data/dxl_mx_info.yml` of ROBOTIS-GIT/emanual hold the `stalltorque` and
# `noloadspeed` strings that `_includes/en/dxl/specifications_x.md` renders, per page `ref`, as the
# page's Specifications table (the figure at the recommended voltage is printed in bold there).
EMANUAL_X_INFO = ("https://github.com/ROBOTIS-GIT/emanual/blob/00280385680aba081862d0854c95de523c6391e6/"
                  "_data/dxl_x_info.yml")
EMANUAL_MX_INFO = ("https://github.com/ROBOTIS-GIT/emanual/blob/0ba8ce0815a0d44d27f7f08bdd8100347d2b9234/"
                   "_data/dxl_mx_info.yml")


@dataclass(frozen=True)
class MotorSpec:
    rpm: float | None      # no-load speed [rev/min]
    nm: float | None       # stall torque [N.m]
    amps: float | None     # stall current [A]
    volts: float           # the input voltage all three are stated at
    source: str            # where they were read (URL and the quoted text)
    missing: str = ""      # why a None figure is absent


def x_info(key: str, torque: str, speed: str, page: str) -> str:
    return (f"{EMANUAL_X_INFO}, key '{key}': stalltorque '{torque}', noloadspeed '{speed}' (the data the "
            f"Specifications table of {page} is rendered from)")


def mx_info(key: str, torque: str, speed: str) -> str:
    return f"{EMANUAL_MX_INFO}, key '{key}': stalltorque '{torque}', noloadspeed '{speed}'"


# The P and PRO pages state no stall figures at all: only no-load speed and current and the
# continuous (rated) operating point, which is not a stall point.
P_PRO_MISSING = ("stall_torque_nm and stall_current_a omitted: the e-Manual states no stall torque or stall "
                 "current for this model, only the continuous operating point ('Continuous Speed {speed} "
                 "[rev/min]', 'Continuous Torque {torque} [N.m]', 'Continuous Current {amps} [A]', 'calculated "
                 "based on the specifications of the core motor'), which is a rated load, not a stall; no "
                 "stated stall figure was found elsewhere")

EXTERNAL_SPECS = {
    "xm430-w350": MotorSpec(46, 4.1, 2.3, 12.0, x_info(
        "xm430-w350", "**4.1 [N.m] (at 12.0 [V], 2.3 [A])**", "**46 [rev/min] (at 12.0 [V])**",
        "https://emanual.robotis.com/docs/en/dxl/x/xm430-w350/") + "; an older revision of the page "
        "(ROBOTIS-GIT/emanual docs/en/dxl/x/xm430-w350.md at 07fe860b) prints the same '4.1Nm @ 12.0V, 2.3A' "
        "and '46rpm @ 12.0V' with 'Recommended : 12.0V'"),
    "xm430-w210": MotorSpec(77, 3.0, 2.3, 12.0, x_info(
        "xm430-w210", "**3.0 [N.m] (at 12.0 [V], 2.3 [A])**", "**77 [rev/min] (at 12.0 [V])**",
        "https://emanual.robotis.com/docs/en/dxl/x/xm430-w210/")),
    "xl430-w250": MotorSpec(57, 1.4, 1.3, 11.1, x_info(
        "xl430-w250", "**1.4 [N.m] (at 11.1 [V], 1.3 [A])**", "**57 [rev/min] (at 11.1 [V])**",
        "https://emanual.robotis.com/docs/en/dxl/x/xl430-w250/") + "; recommended input voltage 11.1 V"),
    "xh430-w210": MotorSpec(50, 2.5, 1.3, 12.0, x_info(
        "xh430-w210", "**2.5 [N.m] (at 12.0 [V], 1.3 [A])**", "**50 [rev/min] (at 12.0 [V])**",
        "https://emanual.robotis.com/docs/en/dxl/x/xh430-w210/") + "; an older revision of the page "
        "(ROBOTIS-GIT/emanual docs/en/dxl/x/xh430-w210.md at 00fc3614) prints the same '2.5Nm @ 12.0V, 1.3A' "
        "and '50rpm @ 12.0V' (52 rev/min and 2.6 N.m are the 24 V XH430-V210's figures, not this model's)"),
    "xh430-w350": MotorSpec(30, 3.4, 1.3, 12.0, "https://emanual.robotis.com/docs/en/dxl/x/xh430-w350; "
                            "stall current from " + x_info(
                                "xh430-w350", "**3.4 [N.m] (at 12.0 [V], 1.3 [A])**",
                                "**30 [rev/min] (at 12.0 [V])**",
                                "https://emanual.robotis.com/docs/en/dxl/x/xh430-w350/")),
    "xh540-w150": MotorSpec(70, 7.1, 4.9, 12.0, x_info(
        "xh540-w150", "7.1 [N.m] (at 12.0 [V], 4.9 [A])", "70 [rev/min]) (at 12.0 [V])",
        "https://emanual.robotis.com/docs/en/dxl/x/xh540-w150/") + "; no entry is bold for this key, the "
        "input voltage is 'Recommended : 12.0 [V]'"),
    "xh540-w270": MotorSpec(39, 9.9, 4.9, 12.0, x_info(
        "xh540-w270", "**9.9 [N.m] (at 12.0 [V], 4.9 [A])**", "**39 [rev/min] (at 12.0 [V])**",
        "https://emanual.robotis.com/docs/en/dxl/x/xh540-w270/")),
    "xm540-w150": MotorSpec(53, 7.3, 4.4, 12.0, "https://emanual.robotis.com/docs/en/dxl/x/xm540-w150 "
                            "('7.3 [N.m] (at 12.0 [V], 4.4 [A], 1.659 [Nm/A])', '53 [rev/min] (at 12.0 [V])')"),
    "xm540-w270": MotorSpec(30, 10.6, 4.4, 12.0, "https://emanual.robotis.com/docs/en/dxl/x/xm540-w270 "
                            "('10.6 [N.m] (at 12.0 [V], 4.4 [A], 2.409 [Nm/A])', '30 [rev/min] (at 12.0 [V])')"),
    "xw540-t260": MotorSpec(40, 9.5, 4.9, 12.0, "https://emanual.robotis.com/docs/en/dxl/x/xw540-t260 "
                            "('9.5 [N.m] (at 12.0 [V], 4.9 [A], 1.939 [Nm/A])', '40 [rev/min] (at 12.0 [V])')"),
    "xc430-w150": MotorSpec(106, 1.6, 1.4, 12.0, "https://emanual.robotis.com/docs/kr/dxl/x/xc430-w150 (Korean "
                            "page: '1.6 [N.m] (at 12.0 [V], 1.4 [A], 1.143 [Nm/A])', '106 [rev/min] (at 12.0 [V])')"),
    "xc430-w240": MotorSpec(70, 1.9, 1.4, 12.0, "https://emanual.robotis.com/docs/kr/dxl/x/xc430-w240/ (Korean "
                            "page: '1.9 [N.m] (at 12.0 [V], 1.4 [A])', '70 [rev/min] (at 12.0 [V])')"),
    "2xl430-w250": MotorSpec(57, 1.4, 1.3, 11.1, "https://emanual.robotis.com/docs/en/dxl/x/2xl430-w250/ "
                             "('1.4 [N.m] (at 11.1 [V], 1.3 [A])', '57 [rev/min] (at 11.1 [V])', recommended "
                             "11.1 V)"),
    "xl330-m288": MotorSpec(103, 0.52, 1.47, 5.0, "https://emanual.robotis.com/docs/en/dxl/x/xl330-m288/; stall "
                            "current from " + x_info(
                                "xl330-m288", "**0.52 [N.m] (at 5.0 [V], 1.47 [A])**",
                                "**103 [rev/min] (at 5.0 [V])**",
                                "https://emanual.robotis.com/docs/en/dxl/x/xl330-m288/")),
    "xl330-m077": MotorSpec(383, 0.215, 1.47, 5.0, "https://emanual.robotis.com/docs/en/dxl/x/xl330-m077/; stall "
                            "current from " + x_info(
                                "xl330-m077", "**0.215 [N.m] (at 5.0 [V], 1.47 [A])**",
                                "**383 [rev/min] (at 5.0 [V])**",
                                "https://emanual.robotis.com/docs/en/dxl/x/xl330-m077/")),
    "xc330-t288": MotorSpec(71, 1.00, 0.88, 12.0, "the 'XC Series' comparison table on "
                            "https://emanual.robotis.com/docs/kr/dxl/x/xl330-m288/ (the highest listed voltage, "
                            "12.0 V, was used since the recommended voltage is not in that table); stall current from "
                            + x_info("xc330-t288", "1.00 [N.m] (at 12.0 [V], 0.88 [A])",
                                     "71 [rev/min] (at 12.0 [V])",
                                     "https://emanual.robotis.com/docs/en/dxl/x/xc330-t288/")
                            + ", which gives the recommended input voltage as 11.1 V (bold there: 0.92 N.m at "
                            "11.1 V, 0.80 A, 65 rev/min); the 12.0 V figures chosen before are kept"),
    "mx-28": MotorSpec(55, 2.5, 1.4, 12.0, "https://emanual.robotis.com/docs/kr/dxl/mx/mx-28/ and the MX overview "
                       "https://emanual.robotis.com/docs/en/dxl/mx/ (same figures for MX-28 Protocol 1.0 and 2.0); "
                       "stall current from " + mx_info("mx-28", "2.5 [Nm] @ 12 [V], 1.4 [A]",
                                                       "55 [rev/min] @ 12 [V]")),
    "mx-28-2": MotorSpec(55, 2.5, 1.4, 12.0, "https://emanual.robotis.com/docs/en/dxl/mx/mx-28-2; stall current "
                         "from " + mx_info("mx-28-2", "2.5 [Nm] @ 12 [V], 1.4 [A]", "55 [rev/min] @ 12 [V]")),
    "mx-106": MotorSpec(45, 8.4, 5.2, 12.0, "https://emanual.robotis.com/docs/en/dxl/mx/mx-106; stall current "
                        "from " + mx_info("mx-106", "8.4 [Nm] @ 12[V], 5.2 [A]", "45 [rev/min] @ 12 [V]")),
    "mx-106-2": MotorSpec(45, 8.4, 5.2, 12.0, "https://emanual.robotis.com/docs/en/dxl/mx/mx-106-2; stall "
                          "current from " + mx_info("mx-106-2", "8.4 [Nm] @ 12[V], 5.2 [A]",
                                                    "45 [rev/min] @ 12 [V]")),
    "ph54-200-s500-r": MotorSpec(33.1, None, None, 24.0, "https://emanual.robotis.com/docs/en/dxl/p/ph54-200-s500-r/ "
                                 "('No Load Speed 33.1 [rev/min]', 'Input Voltage 24.0 [V]'; the same in "
                                 "ROBOTIS-GIT/emanual _data/dxl_p_info.yml)",
                                 missing=P_PRO_MISSING.format(speed="29.0", torque="44.7", amps="9.3")),
    "h54-200-s500-r": MotorSpec(33.1, None, None, 24.0, "https://emanual.robotis.com/docs/en/dxl/pro/h54-200-s500-r "
                                "('No Load Speed 33.1 [rev/min]', 'Input Voltage 24.0 [V]'; the same in "
                                "ROBOTIS-GIT/emanual _data/dxl_pro_info.yml)",
                                missing=P_PRO_MISSING.format(speed="29.0", torque="44.7", amps="9.3")),
}

# Expected Indirect Address / Data blocks: (first n, last n, first address, first data address).
INDIRECT_BLOCKS = {
    "x": [(1, 28, 168, 224), (29, 56, 578, 634)],   # README behaviour 22, X/MX(2.0) pages
    "x330": [(1, 28, 168, 224)],                      # XL330/XC330: only 1 ~ 28
    "mx2": [(1, 28, 168, 224), (29, 56, 578, 634)],
    "p": [(1, 128, 168, 634)],                       # PH54 page: 168 ~ 422, data 634 ~ 761
    "pro": [(1, 256, 49, 634)],                      # H54 page: 49 ~ 559, data 634 ~ 889
}

# Names that differ between an MX(2.0) page and its X donor page (see mx2_donor_range).
NAME_ALIASES = {"protocol version": "protocol type"}

# Why 0 is the power-on value of items the pages print as "-" (key pattern, reason).
ZERO_REASONS = [
    (r"goal_velocity", "motor at rest; Goal Velocity is only used once a velocity mode is commanded"),
    (r"moving_speed", "0 means 'maximum speed, no speed control' in joint mode and stop in wheel mode"),
    (r"realtime_tick", "the millisecond counter starts at power-on"),
    (r"moving|moving_status", "not moving at power-on"),
    (r"present_(pwm|current|velocity|load|speed)|velocity_trajectory", "motor at rest at power-on"),
    (r"backup_ready", "no Control Table Backup exists in the factory state"),
    (r"external_port_data_\d+", "nothing connected / outputs low at power-on"),
    (r"profile_(acceleration|velocity)", "no profile, as on the X pages, whose initial value is 0"),
]

# The 2.0 families report these R items in two's complement although the pages print no range.
SIGNED_READBACK = {"present_pwm", "present_current", "present_velocity", "present_position",
                   "present_load", "velocity_trajectory", "position_trajectory"}


# ---------------------------------------------------------------------------------------------
# Range choices for pages without a Range column (AX/RX/EX/MX 1.0) and for items the pages
# leave open. Each entry names its evidence: a file of the reference and text that must occur in
# it (checked at every run), or a public URL for includes that were not copied.
# ---------------------------------------------------------------------------------------------

LEGACY = "control-tables/includes/ax-legacy-page-description-sections.md"


@dataclass(frozen=True)
class RangeChoice:
    families: frozenset
    keys: tuple
    min: int | None
    max: int | None
    evidence: str            # reference-relative file, "PAGE" (the model's own page) or a URL
    quotes: tuple = ()       # at least one must occur in the evidence file (whitespace-normalised)
    note: str = ""
    signed: bool = False


def rc(families, keys, lo, hi, evidence, quotes=(), note="", signed=False):
    if isinstance(keys, str):
        keys = (keys,)
    if isinstance(quotes, str):
        quotes = (quotes,)
    return RangeChoice(frozenset(families.split()), tuple(keys), lo, hi, evidence, tuple(quotes),
                       note, signed)


RANGE_CHOICES = [
    rc("ax rx ex mx1", "id", 0, 253, "control-tables/includes/control_table_id.md",
       "0~253 (0xFD) values can be used as an ID"),
    rc("rx", "baud_rate", 0, 254, "PAGE", "Available value range is 0 ~ 254(0xFE)"),
    rc("ax ex mx1", "baud_rate", 0, 254, "control-tables/rx-24f.md",
       "Available value range is 0 ~ 254(0xFE)",
       note="this page gives no range; the RX pages state 0 ~ 254 with bps = 2,000,000/(value+1), the "
            "formula behind this page's table too (its spec's lowest rate, 2,000,000/255 = 7,843 bps, "
            "is value 254)"),
    rc("ax rx ex mx1", "return_delay_time", 0, 254,
       "control-tables/includes/control_table_return_delay_time.md",
       "Note that the range of values is 0 to 254"),
    rc("ax rx", ("cw_angle_limit", "ccw_angle_limit"), 0, 1023, LEGACY,
       "The range and the unit of the value is the same as Goal Position",
       note="same range as Goal Position(30), 0 ~ 1,023"),
    rc("ex mx1", ("cw_angle_limit", "ccw_angle_limit"), 0, 4095, LEGACY,
       "The range and the unit of the value is the same as Goal Position",
       note="same range as Goal Position(30) in joint mode, 0 ~ 4,095 (CCW Angle Limit defaults to 4,095)"),
    rc("ax rx ex mx1", "temperature_limit", 0, 100, EMANUAL_INCLUDES + "control_table_temp_limit.md",
       note="the page's include is not in the reference; its e-Manual text gives 'Value Range 0 ~ 100'"),
    rc("ax rx ex mx1", ("min_voltage_limit", "max_voltage_limit"), 50, 250, LEGACY,
       "50 to 250 (0x32 ~ 0x96) can be used",
       note="'50 to 250' as in the AX description (its hex '0x96' is a typo for 0xFA; the EX page's own "
            "table also says 50 ~ 250); MX-64/EX default to 240, above the 50 ~ 160 of newer MX text"),
    rc("ax rx ex mx1", "max_torque", 0, 1023, LEGACY, "0 to 1023 (0x3FF) can be used"),
    rc("ax rx ex mx1", "status_return_level", 0, 2, LEGACY, "|2|Return for all commands|"),
    rc("ax rx ex mx1", ("alarm_led", "shutdown"), 0, 127, LEGACY, "|Bit 7|0|-|",
       note="bit mask of the error bits 0 ~ 6; bit 7 is always 0 per the Alarm LED/Shutdown table"),
    rc("ax rx ex mx1", "torque_enable", 0, 1, LEGACY, "|1|Generates Torque by impressing"),
    rc("ax rx ex mx1", "led", 0, 1, LEGACY, "|1|Turn ON the LED|"),
    rc("ax rx ex", ("cw_compliance_margin", "ccw_compliance_margin"), 0, 255, LEGACY,
       "The range of the value is 0~255"),
    rc("ax rx ex", ("cw_compliance_slope", "ccw_compliance_slope"), 0, 254, LEGACY,
       "128(0x80)~254(0xFE)", note="7 steps up to 254 (0xFE) per the Compliance Slope table"),
    rc("ax rx", "goal_position", 0, 1023, LEGACY, "0 to 1023 (0x3FF) is available"),
    rc("ex", "goal_position", 0, 4095, "PAGE", "| Resolution             | 0.06&deg;",
       note="the Goal Position paragraph on this page says '0 to 1023 ... 0.29 degree' (text inherited "
            "from RX pages) but the spec gives 0.06 deg resolution and CCW Angle Limit defaults to "
            "4,095, so the 12-bit range 0 ~ 4,095 is used"),
    rc("mx1", "goal_position", -28672, 28672, EMANUAL_INCLUDES + "control_table_mx_goal_position.md",
       signed=True,
       note="joint mode uses 0 ~ 4,095; multi-turn mode (both angle limits 4,095) uses -28,672 ~ 28,672 "
            "(e-Manual include control_table_mx_goal_position.md, not in the reference), so the item is "
            "signed and the static range is the multi-turn one"),
    rc("ax rx ex", "moving_speed", 0, 2047, "control-tables/includes/control_table_moving_speed.md",
       "0 ~ 2,047(0x7FF) can be used",
       note="joint mode uses 0 ~ 1,023, wheel mode 0 ~ 2,047 (bit 10 = direction); the static range is "
            "the wheel-mode one"),
    rc("mx1", "moving_speed", 0, 2047, "PAGE", ("0~2047 (0X7FF) can be used", "0 ~ 2,047 (0x7FF) can be used"),
       note="joint/multi-turn mode uses 0 ~ 1,023, wheel mode 0 ~ 2,047 (bit 10 = direction); the "
            "static range is the wheel-mode one"),
    rc("ax rx ex mx1", "torque_limit", 0, 1023, LEGACY, "0 to 1023 (0x3FF) is available"),
    rc("ax rx", "present_position", 0, 1023, LEGACY, "The range of the value is 0~1023 (0x3FF)"),
    rc("ex", "present_position", 0, 65535, "PAGE", "The range of the value is 0~65535(0XFFFF)",
       note="wheel mode reports the raw encoder 0 ~ 65,535; joint mode stays within Goal Position's range"),
    rc("mx1", "present_position", -28672, 28672, EMANUAL_INCLUDES + "control_table_mx_goal_position.md",
       signed=True, note="same as Goal Position(30): signed for multi-turn mode"),
    rc("ax rx ex", "present_speed", 0, 2047, LEGACY, "0~2047 (0X7FF) can be used."),
    rc("mx1", "present_speed", 0, 2047, "PAGE", "0 ~ 2,047 (0x000 ~ 0x7FF) can be used"),
    rc("ax rx ex mx1", "present_load", 0, 2047, LEGACY, "The range of the value is 0~2047"),
    rc("ax rx ex mx1", "registered", 0, 1, LEGACY, "|1|There are commands transmitted by REG_WRITE|"),
    rc("ax rx ex mx1", "moving", 0, 1, LEGACY, "|1|Goal position command execution is in progress|"),
    rc("ax rx ex mx1", "lock", 0, 1, LEGACY, "|1|EEPROM area cannot be modified|"),
    rc("ax rx", "punch", 32, 1023, LEGACY, "Can choose vales from 0x20 to 0x3FF"),
    rc("ex mx1", "punch", 0, 1023, LEGACY, "Can choose vales from 0x20 to 0x3FF",
       note="the description allows 0x20 ~ 0x3FF but this page's initial value is 0, outside it; "
            "0 ~ 1,023 is used so the factory value is valid"),
    rc("ex", "sensed_current", 0, 1023, "PAGE", "The range from 0 to 1023 is used"),
    rc("ex mx1", "drive_mode", None, None, "PAGE",
       note="the Drive Mode include of this page is not in the reference (bit 0 direction, bit 1 "
            "master/slave dual mode); no range is stated, so the full width 0 ~ 255 is allowed"),
    rc("mx1", "multi_turn_offset", -24576, 24576, EMANUAL_INCLUDES + "control_table_multiturn_offset.md",
       signed=True, note="'the range is from -24,576 to 24,576' (include not in the reference)"),
    rc("mx1", "resolution_divider", 1, 4, EMANUAL_INCLUDES + "control_table_resolution_divider.md",
       note="'(1 ~ 4 available)' (include not in the reference)"),
    rc("mx1", ("d_gain", "i_gain", "p_gain"), 0, 254, EMANUAL_INCLUDES + "control_table_mx_pid.md",
       note="'Gains values are in between 0 ~ 254' (include not in the reference; the XL-320 table, "
            "which uses the same include, prints 0 ~ 254 as well)"),
    rc("mx1", "goal_acceleration", 0, 254, EMANUAL_INCLUDES + "control_table_goal_acceleration.md",
       note="'It can be used from 0~254(0XFE)' (include not in the reference)"),
    rc("mx1", "current", 0, 4095, "PAGE", "At an idle state without current flow, this value is 2,048(0x800)",
       note="no range stated; 12-bit value centred on 2,048 (= 0 mA, I = 4.5 mA x (value - 2,048)), so "
            "0 ~ 4,095"),
    rc("mx1", "torque_ctrl_mode_enable", 0, 1, "PAGE", "Turn on the torque mode"),
    rc("mx1", "goal_torque", 0, 2047, "PAGE", "You can use 0 ~ 2,047 (0x7FF)",
       note="bit 10 is the direction, so 'cannot be bigger than Torque Limit(34)' applies to bits 0 ~ 9 "
            "only and is not expressed as limit_max"),
    rc("mx2", "acceleration_limit", 0, 32767, EMANUAL_INCLUDES + "control_table_acclimit.md",
       note="'Value Range 0 ~ 32,767' (include not in the reference; X pages have no such item)"),
]


# ---------------------------------------------------------------------------------------------
# Markdown helpers
# ---------------------------------------------------------------------------------------------

ELLIPSES = {"…", "...", "···", "..", "⋯"}


def clean_cell(text: str) -> str:
    """Plain text of a table cell: links, HTML, entities, emphasis and escapes removed."""
    t = re.sub(r"\[([^\]]*)\]\([^)]*\)", r"\1", text)         # [Name](#anchor) -> Name
    t = re.sub(r"<br\s*/?>", " ", t, flags=re.I)
    t = re.sub(r"<sup>(.*?)</sup>", lambda m: {"2": "²"}.get(m.group(1), m.group(1)), t)
    t = re.sub(r"<[^>]+>", "", t)
    t = html.unescape(t)
    t = t.replace("\\", "").replace("**", "").replace("`", "")
    t = re.sub(r"(?<!\w)_(.+?)_(?!\w)", r"\1", t)                # _Modbus_ -> Modbus
    return re.sub(r"\s+", " ", t).strip()


def split_row(line: str) -> list[str]:
    body = line.strip()
    if body.startswith("|"):
        body = body[1:]
    if body.endswith("|"):
        body = body[:-1]
    return [c for c in body.split("|")]


def is_separator(cells: list[str]) -> bool:
    return all(re.fullmatch(r"\s*:?-{2,}:?\s*", c or "") for c in cells)


@dataclass
class Table:
    line: int                 # 0-based line of the header
    header: list[str]         # cleaned header cells
    rows: list[list[str]]     # raw cells (uncleaned) of each data row
    raw_rows: list[str]


def tables_in(lines: list[str], start: int = 0, end: int | None = None) -> list[Table]:
    """Markdown pipe tables between two line numbers."""
    end = len(lines) if end is None else end
    out, i = [], start
    while i < end - 1:
        if lines[i].lstrip().startswith("|") and is_separator(split_row(lines[i + 1])):
            header = [clean_cell(c) for c in split_row(lines[i])]
            rows, raws, j = [], [], i + 2
            while j < end and lines[j].lstrip().startswith("|"):
                rows.append(split_row(lines[j]))
                raws.append(lines[j])
                j += 1
            out.append(Table(i, header, rows, raws))
            i = j
        else:
            i += 1
    return out


def parse_int(text: str) -> int | None:
    """'1,044,479' / '-501,923' / ' 250 ' -> int; anything else -> None."""
    t = text.strip().replace("−", "-")
    if re.fullmatch(r"-?\d{1,3}(,\d{3})+", t):      # thousands separators only in groups of three
        t = t.replace(",", "")
    return int(t) if re.fullmatch(r"-?\d+", t) else None


def norm_space(text: str) -> str:
    return re.sub(r"\s+", " ", text).strip()


def snake_key(name: str) -> str:
    """key = snake_case of the e-Manual name; parenthesised parts dropped."""
    t = re.sub(r"\([^)]*\)", "", name).lower()
    t = re.sub(r"[^a-z0-9]+", "_", t)
    return t.strip("_")


def camel_to_include(tag: str) -> str:
    """<ControlTableOpmodeSix2 /> -> control_table_opmode_six_2 (includes/README naming rule)."""
    parts = re.findall(r"[A-Z][a-z]*|\d+", tag)
    return "_".join(p.lower() for p in parts)


# Tags whose include file has a different name (includes/README.md).
TAG_ALIASES = {"control_table_mx_baudrate": "control_table_baudrate"}


def select_liquid_branch(text: str, group: str) -> str:
    """Keep only the branch of top-level {% if page.product_group==... %} blocks that applies."""
    out, pos = [], 0
    pattern = re.compile(r"{%\s*(if|elsif|else|endif)\b(.*?)%}", re.S)
    depth, taking, taken, buf_start = 0, True, False, 0
    for m in pattern.finditer(text):
        kind, cond = m.group(1), m.group(2)
        if kind == "if":
            depth += 1
            if depth > 1:
                continue
            if taking:
                out.append(text[pos:m.start()])
            groups = re.findall(r"product_group\s*==\s*'([^']+)'", cond)
            negated = re.findall(r"product_group\s*!=\s*'([^']+)'", cond)
            taken = (group in groups) if groups else (group not in negated if negated else True)
            taking, pos = taken, m.end()
        elif depth == 1 and kind in ("elsif", "else"):
            if taking:
                out.append(text[pos:m.start()])
            if kind == "elsif":
                groups = re.findall(r"product_group\s*==\s*'([^']+)'", cond)
                taking = (not taken) and group in groups
            else:
                taking = not taken
            taken = taken or taking
            pos = m.end()
        elif kind == "endif":
            if depth == 1:
                if taking:
                    out.append(text[pos:m.start()])
                taking, pos = True, m.end()
            depth -= 1
    out.append(text[pos:])
    return "".join(out)


# ---------------------------------------------------------------------------------------------
# Reference access
# ---------------------------------------------------------------------------------------------

class Reference:
    """Read-only view of ../shared/reference."""

    def __init__(self, root: Path):
        self.root = root
        self.pages_dir = root / "control-tables"
        self.includes_dir = self.pages_dir / "includes"
        if not self.pages_dir.is_dir():
            raise SystemExit(f"convert_models: no control-tables/ under {root}")
        self.tsv = self._read_tsv(root / "models.tsv")
        self._cache: dict[str, str] = {}

    @staticmethod
    def _read_tsv(path: Path) -> dict[str, dict]:
        lines = path.read_text(encoding="utf-8").splitlines()
        cols = lines[0].split("\t")
        rows = {}
        for line in lines[1:]:
            if line.strip():
                row = dict(zip(cols, line.split("\t")))
                rows[row["control_table_file"].removesuffix(".md")] = row
        return rows

    def page_names(self) -> list[str]:
        return sorted(p.stem for p in self.pages_dir.glob("*.md"))

    def text(self, rel: str) -> str:
        if rel not in self._cache:
            self._cache[rel] = (self.root / rel).read_text(encoding="utf-8")
        return self._cache[rel]

    def include(self, name: str, group: str) -> str | None:
        """An include by snake name, Liquid branch for `group` selected; None when not copied."""
        name = TAG_ALIASES.get(name, name)
        path = self.includes_dir / f"{name}.md"
        if not path.exists():
            return None
        return select_liquid_branch(path.read_text(encoding="utf-8"), group)


# ---------------------------------------------------------------------------------------------
# Page parsing
# ---------------------------------------------------------------------------------------------

@dataclass
class Row:
    """One control-table row as printed (after ellipsis expansion, `expanded` is True)."""
    address: int
    size: int
    name: str
    access: str
    initial: str
    range: str
    unit: str
    minmax: tuple | None      # XL-320 Min/Max columns
    area: str
    expanded: bool = False


@dataclass
class Section:
    """A 'Control Table Description' section: its heading, addresses and text."""
    title: str
    addresses: list[int]
    start: int
    end: int


@dataclass
class Page:
    name: str
    family: str
    group: str
    lines: list[str]
    rows: list[Row]
    sections: list[Section]
    columns: set

    @property
    def text(self) -> str:
        return "\n".join(self.lines)

    def section_for(self, address: int) -> list[Section]:
        return [s for s in self.sections if address in s.addresses]

    def section_text(self, sec: Section, ref: Reference) -> str:
        """Section text with its include tags expanded (includes that were copied)."""
        chunk = "\n".join(self.lines[sec.start:sec.end])

        def expand_tag(m):
            inc = ref.include(TAG_ALIASES.get(camel_to_include(m.group(1)), camel_to_include(m.group(1))),
                              self.group)
            return inc if inc is not None else m.group(0)

        def expand_liquid(m):
            inc = ref.include(m.group(1), self.group)
            return inc if inc is not None else m.group(0)

        chunk = re.sub(r"<(ControlTable\w+)\s*/>", expand_tag, chunk)
        return re.sub(r"{%\s*include\s+en/dxl/([\w]+)\.md\s*%}", expand_liquid, chunk)


COLUMN_PATTERNS = [
    ("address", r"^address$"), ("size", r"^size"), ("name", r"^data name$"),
    ("description", r"^description$"), ("access", r"^access$"), ("initial", r"^initial"),
    ("range", r"^range$"), ("unit", r"^unit$"), ("min", r"^min$"), ("max", r"^max$"),
    ("modbus", r"modbus"),
]


def map_columns(header: list[str]) -> dict[str, int]:
    """Column index by meaning, located by header text (column sets differ between pages)."""
    cols = {}
    for idx, h in enumerate(header):
        for key, pat in COLUMN_PATTERNS:
            if re.search(pat, h.lower()) and key not in cols:
                cols[key] = idx
                break
    for needed in ("address", "size", "name", "access", "initial"):
        if needed not in cols:
            raise ValueError(f"control table header lacks {needed!r}: {header}")
    return cols


def control_tables(lines: list[str]) -> list[tuple[str, Table]]:
    """The EEPROM and RAM tables: first table after a 'Control Table of ... Area' heading."""
    found = []
    for i, line in enumerate(lines):
        m = re.match(r"#+\s.*Control Table of (EEPROM|RAM) Area", line)
        if m:
            tabs = tables_in(lines, i + 1, min(len(lines), i + 400))
            if not tabs:
                raise ValueError(f"no table after {line!r}")
            found.append((m.group(1), tabs[0]))
    return found


def read_rows(area: str, table: Table) -> list[dict]:
    cols = map_columns(table.header)
    out = []
    for cells, raw in zip(table.rows, table.raw_rows):
        if len(cells) < len(table.header):
            cells = cells + [""] * (len(table.header) - len(cells))

        def cell(key, raw_cell=False):
            if key not in cols:
                return ""
            return cells[cols[key]] if raw_cell else clean_cell(cells[cols[key]])

        out.append({
            "area": area, "address": cell("address"), "size": cell("size"), "name": cell("name"),
            "access": cell("access"), "initial": cell("initial"), "range": cell("range"),
            "unit": clean_cell(re.sub(r"<br\s*/?>", " / ", cell("unit", raw_cell=True))) if "unit" in cols else "",
            "min": cell("min"), "max": cell("max"),
            "has_minmax": "min" in cols, "raw": raw,
        })
    return out


def is_ellipsis_row(r: dict) -> bool:
    return parse_int(r["address"]) is None


def numbered(name: str) -> tuple[str, int] | None:
    m = re.fullmatch(r"(.*?)\s*(\d+)", name)
    return (m.group(1), int(m.group(2))) if m else None


def expand_ellipses(raw: list[dict]) -> list[Row]:
    """Replace '…' rows by the series they stand for, from the two rows before and the row after.

    Address step and initial-value step come from the two preceding rows; the row after the
    ellipsis must land exactly where the series predicts, otherwise the page is not understood.
    """
    rows: list[Row] = []

    def to_row(r: dict, expanded=False) -> Row:
        mm = None
        if r["has_minmax"]:
            mm = (r["min"], r["max"])
        return Row(parse_int(r["address"]), parse_int(r["size"]), r["name"], r["access"], r["initial"],
                   r["range"], r["unit"], mm, r["area"], expanded)

    i = 0
    while i < len(raw):
        r = raw[i]
        if not is_ellipsis_row(r):
            row = to_row(r)
            if row.size is None:
                raise ValueError(f"row without a size: {r['raw']}")
            rows.append(row)
            i += 1
            continue
        if len(rows) < 2 or i + 1 >= len(raw):
            raise ValueError(f"ellipsis row without neighbours: {r['raw']}")
        prev2, prev, nxt = rows[-2], rows[-1], to_row(raw[i + 1])
        a, b, c = numbered(prev2.name), numbered(prev.name), numbered(nxt.name)
        if not (a and b and c) or not (a[0] == b[0] == c[0]) or b[1] != a[1] + 1:
            raise ValueError(f"cannot expand ellipsis between {prev.name!r} and {nxt.name!r}")
        base, count = b[0], c[1] - b[1] - 1
        step = prev.address - prev2.address
        init_a, init_b, init_c = parse_int(prev2.initial), parse_int(prev.initial), parse_int(nxt.initial)
        init_step = (init_b - init_a) if init_a is not None and init_b is not None else None
        if prev.address + step * (count + 1) != nxt.address:
            raise ValueError(f"ellipsis before {nxt.name}: address series does not reach {nxt.address}")
        if init_step is not None and init_c is not None and init_b + init_step * (count + 1) != init_c:
            raise ValueError(f"ellipsis before {nxt.name}: initial series does not reach {init_c}")
        for k in range(1, count + 1):
            initial = str(init_b + init_step * k) if init_step is not None else prev.initial
            rows.append(Row(prev.address + step * k, prev.size, f"{base} {b[1] + k}", prev.access, initial,
                            prev.range, prev.unit, prev.minmax, prev.area, expanded=True))
        i += 1
    return rows


HEADING_RE = re.compile(r"^(#{2,5})\s+(.*)$")


def description_sections(lines: list[str]) -> list[Section]:
    """Sections below 'Control Table Description', with the addresses named in their heading."""
    start = next((i for i, l in enumerate(lines) if re.match(r"#+\s.*Control Table Description", l)), None)
    if start is None:
        return []
    heads = []
    for i in range(start + 1, len(lines)):
        m = HEADING_RE.match(lines[i])
        if m:
            heads.append((i, clean_cell(m.group(2))))
    sections = []
    for n, (i, title) in enumerate(heads):
        end = heads[n + 1][0] if n + 1 < len(heads) else len(lines)
        addrs = []
        for group in re.findall(r"\(([\d,\s]+)\)", title):
            addrs += [int(x) for x in re.findall(r"\d+", group)]
        sections.append(Section(title, addrs, i + 1, end))
    return sections


def read_page(ref: Reference, name: str) -> Page:
    lines = ref.text(f"control-tables/{name}.md").splitlines()
    family = family_of(name)
    raw, columns = [], set()
    tabs = control_tables(lines)
    if [a for a, _ in tabs] != ["EEPROM", "RAM"]:
        raise ValueError(f"{name}: expected an EEPROM and a RAM table, found {[a for a, _ in tabs]}")
    for area, table in tabs:
        columns |= set(map_columns(table.header))
        raw += read_rows(area, table)
    rows = expand_ellipses(raw)
    return Page(name, family, product_group(name, family), lines, rows, description_sections(lines), columns)


# ---------------------------------------------------------------------------------------------
# Cell interpretation
# ---------------------------------------------------------------------------------------------

RANGE_RE = re.compile(r"(-?[\d,]+)\s*~\s*(-?[\d,]+)")
LIMIT_RE = re.compile(r"^(-?)\s*([A-Za-z][A-Za-z ]*?)\s*\((\d+)\)$")


@dataclass
class RangeSpec:
    """What a Range cell says."""
    min: int | None = None
    max: int | None = None
    values: list | None = None
    lo_ref: tuple | None = None   # (negated, name, address)
    hi_ref: tuple | None = None
    extra: list = field(default_factory=list)   # further ranges printed in the same cell
    raw: str = ""


def parse_range(cell: str) -> RangeSpec | None:
    """Range cell -> RangeSpec; None for '-' / empty."""
    t = clean_cell(cell)
    if t in ("", "-") or t in ELLIPSES:
        return None
    spec = RangeSpec(raw=t)
    if "~" in t:
        lo, hi = [s.strip() for s in t.split("~", 1)]
        # "0 ~ 32,767 0 ~ 32,737": two ranges in one cell (velocity- vs time-based profile)
        ranges = RANGE_RE.findall(t)
        if len(ranges) > 1 and parse_int(ranges[0][0]) is not None:
            spec.min, spec.max = parse_int(ranges[0][0]), parse_int(ranges[0][1])
            spec.extra = [(parse_int(a), parse_int(b)) for a, b in ranges[1:]]
            return spec
        # "0 ~ 252 (DYNAMIXEL Protocol 2.0) 1 ~ 247 (Modbus)"
        if ranges and "(" in t and parse_int(lo) is not None:
            spec.min, spec.max = parse_int(ranges[0][0]), parse_int(ranges[0][1])
            spec.extra = [(parse_int(a), parse_int(b)) for a, b in ranges[1:]]
            return spec
        for side, text in (("lo", lo), ("hi", hi)):
            n = parse_int(text)
            if n is not None:
                setattr(spec, "min" if side == "lo" else "max", n)
                continue
            m = LIMIT_RE.match(text)
            if not m:
                raise ValueError(f"range cell not understood: {t!r}")
            setattr(spec, f"{side}_ref", (m.group(1) == "-", m.group(2).strip(), int(m.group(3))))
        return spec
    if "," in t and all(parse_int(x) is not None for x in t.split(",")):
        spec.values = [parse_int(x) for x in t.split(",")]
        return spec
    n = parse_int(t)
    if n is not None:
        spec.values = [n]     # a lone number (Startup Configuration's "3"): resolved by the caller
        return spec
    raise ValueError(f"range cell not understood: {t!r}")


def clean_unit(unit: str) -> str | None:
    u = norm_space(unit.replace("[ ", "[").replace(" ]", "]"))
    u = re.sub(r"\s+\]", "]", u)
    return None if u in ("", "-") or u in ELLIPSES else u


def unit_number(unit: str | None) -> float | None:
    if not unit:
        return None
    m = re.match(r"(?:about\s*)?([\d.]+)", unit.strip(), re.I)
    return float(m.group(1)) if m else None


def full_width(size: int, signed: bool) -> tuple[int, int]:
    bits = 8 * size
    return (-(1 << (bits - 1)), (1 << (bits - 1)) - 1) if signed else (0, (1 << bits) - 1)


# ---------------------------------------------------------------------------------------------
# Building items
# ---------------------------------------------------------------------------------------------

@dataclass
class Item:
    row: Row
    key: str
    initial: int | None = None
    initial_from: str | None = None
    signed: bool = False
    min: int | None = None
    max: int | None = None
    values: list | None = None
    limit_min: str | None = None
    limit_max: str | None = None
    unit: str | None = None
    notes: list = field(default_factory=list)
    range_from: str = ""       # "table", "choice", ... (for the summary)

    def to_json(self) -> dict:
        d = {"key": self.key, "name": self.row.name, "address": self.row.address, "size": self.row.size,
             "access": self.access, "area": self.row.area}
        if self.initial_from is not None:
            d["initial_from"] = self.initial_from
        else:
            d["initial"] = self.initial
        if self.signed:
            d["signed"] = True
        if self.min is not None:
            d["min"] = self.min
        if self.max is not None:
            d["max"] = self.max
        if self.values is not None:
            d["values"] = self.values
        if self.limit_min is not None:
            d["limit_min"] = self.limit_min
        if self.limit_max is not None:
            d["limit_max"] = self.limit_max
        if self.unit:
            d["unit"] = self.unit
        if self.notes:
            d["note"] = "; ".join(self.notes)
        return d

    @property
    def access(self) -> str:
        return "RW" if self.row.access == "R/RW" else self.row.access


class ModelBuilder:
    """Turns one page into one model dict, recording every decision."""

    def __init__(self, ref: Reference, page: Page, donors: dict[str, Page]):
        self.ref, self.page, self.donors = ref, page, donors
        self.name, self.family = page.name, page.family
        self.tsv = ref.tsv[page.name]
        self.notes: list[str] = []
        self.items: list[Item] = []
        self.by_key: dict[str, Item] = {}
        self.by_addr: dict[int, Item] = {}

    # -- helpers ------------------------------------------------------------------------------

    @property
    def fw_family(self) -> str:
        return "x330" if self.name in X330 else self.family

    def section_ranges(self, item: Item) -> list[RangeSpec]:
        """Ranges stated in small 'Unit | Value Range' tables of the item's description section."""
        out = []
        for sec in self.page.section_for(item.row.address):
            for tab in tables_in(self.page.section_text(sec, self.ref).splitlines()):
                # 'Unit | Value Range' / 'Unit | Range' tables; mode and bit tables have no such column
                idx = next((k for k, h in enumerate(tab.header) if "range" in h.lower()), None)
                if idx is None:
                    continue
                for cells in tab.rows:
                    if idx < len(cells):
                        try:
                            spec = parse_range(cells[idx])
                        except ValueError:
                            continue
                        if spec and (spec.min is not None or spec.lo_ref):
                            out.append(spec)
        return out

    def evidence_ok(self, choice: RangeChoice) -> bool:
        if choice.evidence.startswith("http"):
            return True
        text = self.page.text if choice.evidence == "PAGE" else self.ref.text(choice.evidence)
        flat = norm_space(text)
        return not choice.quotes or any(norm_space(q) in flat for q in choice.quotes)

    def choice_for(self, key: str) -> RangeChoice | None:
        for choice in RANGE_CHOICES:
            if self.family in choice.families and key in choice.keys:
                if not self.evidence_ok(choice):
                    raise SystemExit(f"convert_models: {self.name}.{key}: evidence {choice.quotes!r} "
                                     f"not found in {choice.evidence}")
                return choice
        return None

    def mx2_donor_range(self, row: Row) -> tuple[str, str, str] | None:
        """Range cell of the same item on an X page (MX(2.0) pages have no Range column).

        The MX(2.0) and X pages describe these items with the same shared include blocks, and the
        X tables print the ranges those blocks state. The donor item must have the same address,
        size and name.
        """
        want = NAME_ALIASES.get(row.name.lower(), row.name.lower())
        for dname, donor in self.donors.items():
            for drow in donor.rows:
                if drow.address == row.address and drow.size == row.size and \
                        NAME_ALIASES.get(drow.name.lower(), drow.name.lower()) == want and \
                        parse_range(drow.range) is not None:
                    return dname, drow.range, drow.unit
        return None

    # -- pass 1: identity, access, printed range ------------------------------------------------

    def make_items(self):
        keys_seen: dict[str, Row] = {}
        for row in self.page.rows:
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
            self.items.append(item)
            self.by_key[item.key] = item
            self.by_addr[row.address] = item

    def ref_key(self, ref: tuple, item: Item) -> tuple[str, Item]:
        negated, name, addr = ref
        target = self.by_addr.get(addr)
        if target is None or snake_key(target.row.name) != snake_key(name):
            raise ValueError(f"{self.name}.{item.key}: range names {name}({addr}), which is not an item")
        return ("-" if negated else "") + target.key, target

    def apply_spec(self, item: Item, spec: RangeSpec, source: str):
        """Set min/max/values/limits of `item` from a parsed Range cell."""
        key = item.key
        if spec.values is not None and len(spec.values) == 1 and spec.min is None:
            # Startup Configuration prints '3': the mask of its two defined bits.
            item.min, item.max = 0, spec.values[0]
            item.notes.append(f"range: {source} prints '{spec.raw}'; read as the bit mask of bits 0 ~ 1 "
                              f"(bit0 Startup Torque On, bit1 RAM Restore; bits 2 ~ 7 'Unused, always 0' "
                              f"per the Startup Configuration include), i.e. 0 ~ {spec.values[0]}")
            return
        if spec.values is not None:
            item.values = spec.values
            return
        item.min, item.max = spec.min, spec.max
        if spec.extra:
            if key == "profile_acceleration":
                lo2, hi2 = spec.extra[0]
                item.notes.append(f"range: {source} prints '{spec.raw}' (velocity-based profile 0 ~ {spec.max:,}, "
                                  f"time-based profile 0 ~ {hi2:,} ms, Drive Mode bit 2); the static range is the "
                                  f"wider velocity-based one; in time-based mode the emulator must also refuse "
                                  f"values above {hi2:,} and cap acceleration time at 50% of Profile Velocity")
                item.max = max(spec.max, hi2)
            else:
                item.notes.append(f"range: {source} prints '{spec.raw}'; the first range (DYNAMIXEL Protocol "
                                  f"2.0) is used, the other applies to a protocol dxlemu does not emulate")
        for side in ("lo", "hi"):
            ref = getattr(spec, f"{side}_ref")
            if ref:
                k, target = self.ref_key(ref, item)
                setattr(item, "limit_min" if side == "lo" else "limit_max", k)

    def printed_ranges(self):
        for item in self.items:
            row = item.row
            spec = None
            if row.minmax is not None:       # XL-320: Min / Max columns
                lo, hi = (parse_int(x) for x in row.minmax)
                if lo is not None and hi is not None:
                    spec = RangeSpec(min=lo, max=hi, raw=f"{row.minmax[0]} ~ {row.minmax[1]}")
            elif "range" in self.page.columns:
                spec = parse_range(row.range)
            if spec is not None:
                item.range_from = "table"
                self.apply_spec(item, spec, "the table")

    # -- pass 2: ranges the table does not print ---------------------------------------------

    def fill_unprinted_ranges(self):
        for item in self.items:
            if item.range_from:
                continue
            # 1. a small range table in the item's own description section
            specs = self.section_ranges(item)
            if specs:
                self.apply_spec(item, specs[0], "its description section")
                item.range_from = "description"
                title = self.page.section_for(item.row.address)[0].title
                item.notes.append(f"range: the table has no range for this item; '{specs[0].raw}' is stated "
                                  f"in the description section '{title}' (with its include blocks)")
                continue
            # 2. a documented choice with its evidence
            choice = self.choice_for(item.key)
            if choice:
                item.range_from = "choice"
                if choice.min is None:
                    item.notes.append(f"range: {choice.note}")
                    continue
                item.min, item.max = choice.min, choice.max
                item.signed = item.signed or choice.signed
                where = choice.evidence if choice.evidence != "PAGE" else "this page"
                quote = norm_space(clean_cell(choice.quotes[0]).replace("|", " ")) if choice.quotes else ""
                if quote and choice.evidence != "PAGE":
                    where = f"{choice.evidence} ('{quote}')"
                elif quote:
                    where = f"this page ('{quote}')"
                text = f"range: the page has no Range column; {choice.min} ~ {choice.max} from {where}"
                if choice.note:
                    text += f"; {choice.note}"
                item.notes.append(text)
                continue
            # 3. MX(2.0): the same item on the X pages
            if self.family == "mx2":
                donor = self.mx2_donor_range(item.row)
                if donor:
                    dname, cell, _ = donor
                    self.apply_spec(item, parse_range(cell), f"the {dname} table")
                    item.range_from = "donor"
                    item.notes.append(f"range: the MX(2.0) page has no Range column; '{clean_cell(cell)}' is taken "
                                      f"from the same item in control-tables/{dname}.md, whose description uses the "
                                      f"same shared include block")
                    continue
            # 4. nothing stated: the full width of the item (the format's default)
            item.range_from = "default"
            why = "read-only, " if item.access == "R" else ""
            item.notes.append(f"range: {why}no range printed or described; the full width of the item "
                              f"(format default) applies")

    # -- pass 3: signedness, operating modes, special items -----------------------------------

    def page_has_extended_mode(self) -> bool:
        """True when the model's Operating Mode accepts 4 (Extended Position Control Mode)."""
        mode = next((i for i in self.items if i.key == "operating_mode"), None)
        return mode is not None and (4 in (mode.values or []) or
                                     (mode.max is not None and mode.max >= 4))

    def signedness(self):
        for item in self.items:
            if (item.min is not None and item.min < 0) or (item.values and min(item.values) < 0):
                item.signed = True
            if item.limit_min and item.limit_min.startswith("-"):
                item.signed = True
            if self.family in P2_FAMILIES and item.key in SIGNED_READBACK and not item.signed:
                item.signed = True
                item.notes.append("signed: the page prints no range, but the device reports this value in "
                                  "two's complement (negative for reverse direction / below zero)")
            if (item.key == "goal_position" and self.family in P2_FAMILIES and not item.signed
                    and self.page_has_extended_mode()):
                item.signed = True
                item.notes.append("signed: Extended Position Control Mode (Operating Mode 4) takes goals of "
                                  "-256 ~ 256 rev in two's complement (opmode include); the range rule of the "
                                  "motion model widens the static range in that mode")
            if item.key == "bus_watchdog" and self.family in ("x", "mx2", "p"):
                item.signed = True
                printed = f"{item.min} ~ {item.max}"
                why = ""
                if item.min and item.min > 0:
                    item.min = 0
                    why = (f"range: {printed} is printed for the active values; 0 (deactivate, clear the "
                           f"watchdog error) is accepted too, per the Bus Watchdog include's Values table; ")
                item.notes.append(f"{why}signed: the device itself sets -1 (0xFF) on a watchdog timeout (Bus "
                                  f"Watchdog include), so the item is signed; writes accept {item.min} ~ {item.max}")
        if self.family in P2_FAMILIES:
            self.notes.append("signed: Present PWM/Current/Load/Velocity/Position and Velocity/Position Trajectory "
                              "print no range but are two's-complement values on Protocol 2.0 devices "
                              "(README behaviour 20); they are marked signed")
        if self.family in V1_FAMILIES or self.family == "xl320":
            self.notes.append("signed: Present Speed / Present Load (and Moving Speed, Goal Torque) encode the "
                              "direction in bit 10 (0 ~ 2,047), so they stay unsigned")

    def operating_modes(self):
        item = self.by_key.get("operating_mode")
        if item is None:
            return
        if item.values is not None:          # P / PRO print the list
            return
        text = self.page.text
        tags = [("OpmodeSix2", "opmode_six_2", "control_table_opmode_six_2"),
                ("MxOpmode2", "mx_opmode_2", "control_table_mx_opmode_2")]
        for tag, inc_name, file in tags:
            if f"ControlTable{tag}" in text or f"control_table_{inc_name}.md" in text:
                item.values = self.mode_values(file)
                item.notes.append(f"values: the modes listed in {file}.md (the page's Operating Mode block)")
                return
        if "<OperatingModeXl />" in text:
            assert "goal_current" not in self.by_key
            item.values = self.mode_values("control_table_mx_opmode_2")
            item.notes.append("values: the page's <OperatingModeXl /> block is not in the reference; this model "
                              "has no Goal Current item (no current sensing), so the four non-current modes "
                              "of control_table_mx_opmode_2.md are used: 1, 3, 4, 16")
            return
        raise ValueError(f"{self.name}: no Operating Mode block recognised")

    def mode_values(self, include: str) -> list[int]:
        text = self.ref.include(include, self.page.group)
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

    def protocol_type_values(self):
        item = self.by_key.get("protocol_type")
        if item is None or self.name not in X330:
            return
        text = self.ref.include("control_table_protocolversion", self.page.group)
        tab = next(t for t in tables_in(text.splitlines()) if t.header[0].lower() == "value")
        item.values = [int(re.match(r"\s*(\d+)", clean_cell(c[0])).group(1)) for c in tab.rows]
        item.notes.append(f"values: the table prints 2 ~ 22; the accepted values are those of the XL330/XC330 "
                          f"Protocol Type block (control_table_protocolversion.md): "
                          f"{', '.join(map(str, item.values))}")

    def baud_rate_values(self):
        """PRO prints 0 ~ 13 but its baud include lists only 0 ~ 8."""
        item = self.by_key.get("baud_rate")
        if self.family == "pro":
            item.values = [i for i, _ in EXTERNAL_BAUD["pro"][0]]
            item.notes.append("values: the table prints 0 ~ 13 but the PRO Baud Rate include "
                              f"({EXTERNAL_BAUD['pro'][1]}) defines only 0 ~ 8; values 9 ~ 13 select no bit "
                              "rate, so only 0 ~ 8 are accepted")

    # -- pass 4: static ranges of limit-bounded items, initial values -------------------------

    def resolve_limits(self):
        for item in self.items:
            for side in ("limit_min", "limit_max"):
                ref = getattr(item, side)
                if not ref:
                    continue
                target = self.by_key[ref.lstrip("-")]
                lo, hi = self.static_range(target)
                if ref.startswith("-"):
                    bound = -hi
                else:
                    bound = lo if side == "limit_min" else hi
                if side == "limit_min" and item.min is None:
                    item.min = bound
                if side == "limit_max" and item.max is None:
                    item.max = bound
            if item.min is not None and item.min < 0:
                item.signed = True      # e.g. P/PRO Goal Position between negative position limits
            if item.limit_min or item.limit_max:
                item.notes.append(f"range: bounded by {item.limit_min or item.min} ~ {item.limit_max or item.max}; "
                                  f"the static min/max ({item.min} ~ {item.max}) are the bounding items' own "
                                  f"static range")
        for item in self.items:
            if item.min is not None and item.max is None or item.max is not None and item.min is None:
                raise ValueError(f"{self.name}.{item.key}: half a range")

    def static_range(self, item: Item) -> tuple[int, int]:
        if item.min is not None:
            return item.min, item.max
        return full_width(item.row.size, item.signed)

    def initial_values(self, fw: int):
        mid_position = {"x": 2048, "mx2": 2048, "mx1": 2048, "ex": 2048, "ax": 512, "rx": 512,
                        "xl320": 512, "p": 0, "pro": 0}[self.family]
        vmin = self.by_key.get("min_voltage_limit")
        vmax = self.by_key.get("max_voltage_limit")
        for item in self.items:
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
                item.initial = self.static_range(item)[1]
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
                    raise ValueError(f"{self.name}.{key}: initial {what} and no rule for it")
                item.notes.append(f"initial: the page shows {what}; 0 chosen ({reason})")

    # -- model level ----------------------------------------------------------------------------

    def baud_rates(self) -> tuple[list[dict], int]:
        fam = self.family
        if fam in EXTERNAL_BAUD:
            table, url = EXTERNAL_BAUD[fam]
            self.notes.append(f"baud_rates: the page's Baud Rate include is not in the reference; the table is "
                              f"from {url} (nominal rates)")
            rates = table
        else:
            rates = self.parse_baud_tables()
        default = self.by_key["baud_rate"].initial
        if fam in ("ax", "rx", "ex", "mx1"):
            self.notes.append("baud_rates: Baud Rate value n means 2,000,000/(n+1) bps for every n in 0 ~ 254 "
                              "(MX 1.0: 250/251/252 are 2.25M/2.5M/3M); only the values the page's table "
                              "lists are enumerated (the format cannot state the formula); the item accepts "
                              "0 ~ 254")
        return [{"index": i, "bps": b} for i, b in sorted(rates)], default

    def parse_baud_tables(self) -> list[tuple[int, int]]:
        secs = [s for s in self.page.sections if "baud rate" in s.title.lower()]
        if not secs:
            raise ValueError(f"{self.name}: no Baud Rate section")
        text = self.page.section_text(secs[0], self.ref)
        rates = {}
        for tab in tables_in(text.splitlines()):
            if not tab.header or tab.header[0].lower() != "value":
                continue
            bcol = next(i for i, h in enumerate(tab.header) if "baud" in h.lower())
            for cells in tab.rows:
                idx = re.match(r"\s*(\d+)", clean_cell(cells[0]))
                bps = parse_bps(clean_cell(cells[bcol]))
                if idx and bps:
                    rates[int(idx.group(1))] = bps
        if not rates:
            raise ValueError(f"{self.name}: no baud table found")
        return list(rates.items())

    def motion(self) -> dict:
        fam, notes = self.family, self.notes
        if fam in ("x", "mx2", "mx1"):
            dpp = 360 / 4096
            notes.append("motion.degrees_per_pulse: 360/4096 (4,096 pulses per revolution, Unit column '1 [pulse]' "
                         "/ models.tsv '4096 pulse/rev')")
        elif fam in ("ax", "rx", "xl320"):
            dpp = 300 / 1024
            notes.append("motion.degrees_per_pulse: 300/1024 = 0.29296875 (the spec's 'Resolution 0.29 deg': Goal "
                         "Position 0 ~ 1,023 over 0 ~ 300 deg, 512 = 150 deg)")
        elif fam == "ex":
            dpp = 251 / 4096
            notes.append("motion.degrees_per_pulse: 251/4096 = 0.0613 (spec: 'Resolution 0.06 deg', 'Running Degree "
                         "0 ~ 251 deg' over 4,096 positions); the page's Goal Position text still says 0.29 deg "
                         "(inherited from RX pages, see README inconsistencies)")
        elif fam == "p":
            dpp = float(Fraction(180, 501923))
            notes.append("motion.degrees_per_pulse: 180/501,923 (Goal Position description: -180 ~ 180 deg = "
                         "-501,923 ~ 501,923)")
        else:
            dpp = float(Fraction(180, 250961))
            notes.append("motion.degrees_per_pulse: 180/250,961, derived from the default position limits "
                         "+-250,961 taken as +-180 deg (models.tsv: 'derived from defaults, not stated')")
        m = {"degrees_per_pulse": dpp, "velocity_unit_rpm": self.velocity_unit()}
        cur = self.current_unit()
        if cur is not None:
            m["current_unit_ma"] = cur
        self.specs(m)
        self.acceleration_unit(m)
        return m

    def velocity_unit(self) -> float:
        col = self.tsv["max_speed_units"]
        mt = re.search(r"x ([\d.]+) rev/min|about ([\d.]+) ?rpm/unit", col)
        if not mt:
            raise ValueError(f"{self.name}: no velocity unit in models.tsv")
        v = float(mt.group(1) or mt.group(2))
        for key in ("velocity_limit", "goal_velocity", "profile_velocity"):
            item = self.by_key.get(key)
            if item and item.unit and unit_number(item.unit) not in (None, v):
                raise ValueError(f"{self.name}: velocity unit {item.unit} disagrees with models.tsv {v}")
        self.notes.append(f"motion.velocity_unit_rpm: {v} rev/min per unit (models.tsv '{col.strip()}')")
        return v

    def current_unit(self) -> float | None:
        for key in ("current_limit", "goal_current", "present_current", "goal_torque", "torque_limit"):
            item = self.by_key.get(key)
            if item and item.unit and "mA" in item.unit:
                u = unit_number(item.unit)
                self.notes.append(f"motion.current_unit_ma: {u} (Unit column of {item.row.name}: '{item.unit}')")
                return u
        text = self.page.text
        for pat, what in ((r"\|\s*about\s+([\d.]+)\s*\[mA\]", "the Current Limit description table"),
                          (r"I = \( ([\d.]+)mA \)", "the Current(68) description 'I = ( 4.5mA ) * (CURRENT - 2048)'"),
                          (r"the unit is (\d+)mA", "the Sensed Current(56) description")):
            mt = re.search(pat, text)
            if mt:
                u = float(mt.group(1))
                self.notes.append(f"motion.current_unit_ma: {u} ({what})")
                return u
        return None

    def specs(self, m: dict):
        """no_load_speed_rpm / stall_torque_nm / stall_current_a / nominal_voltage_v from the page's
        Specifications table, else EXTERNAL_SPECS."""
        fields = "motion.no_load_speed_rpm / stall_torque_nm / stall_current_a / nominal_voltage_v"
        page_spec = parse_spec_table(self.page.lines)
        if page_spec:
            ps = page_spec
            m["no_load_speed_rpm"], m["stall_torque_nm"] = ps.rpm, ps.nm
            if ps.amps is not None:
                m["stall_current_a"] = ps.amps
            if ps.volts is not None:
                m["nominal_voltage_v"] = float(ps.volts)
            amps = f", {ps.amps} A" if ps.amps is not None else ""
            self.notes.append(f"{fields}: {ps.rpm} rev/min, {ps.nm} N.m{amps} at {ps.volts} V from this page's "
                              f"Specifications table (control-tables/{self.name}.md: Stall Torque "
                              f"'{ps.torque_text}', No Load Speed '{ps.speed_text}'){ps.detail}")
            if ps.amps is None:
                self.notes.append("motion.stall_current_a omitted: the page's Stall Torque row states no current")
            return
        spec = EXTERNAL_SPECS.get(self.name)
        if spec is None:
            self.notes.append("motion: no_load_speed_rpm, stall_torque_nm, stall_current_a and nominal_voltage_v "
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
        self.notes.append(f"motion.{' / '.join(keys + ['nominal_voltage_v'])}: {', '.join(stated)} at {spec.volts} V "
                          f"from the e-Manual specifications: {spec.source}")
        if spec.missing:
            self.notes.append(f"motion: {spec.missing}")

    def acceleration_unit(self, m: dict):
        """acceleration_unit_rpm2: rev/min^2 per unit of Profile Acceleration, from its Unit column or,
        on pages without one (MX(2.0)), the Unit row of its description section."""
        item = self.by_key.get("profile_acceleration")
        if item is None:
            other = self.by_key.get("goal_acceleration")
            extra = (f" (its Goal Acceleration({other.row.address}) is a different item, in '{other.unit}')"
                     if other is not None and other.unit else "")
            self.notes.append(f"motion.acceleration_unit_rpm2 omitted: the model has no Profile Acceleration "
                              f"item{extra}")
            return
        accel = re.compile(r"([\d.,]+)\s*\[rev/min(?:²|2|\^2)\]")
        if item.unit:
            first = item.unit.split(" / ")[0]
            mt = accel.fullmatch(first.strip())
            if not mt:
                self.notes.append(f"motion.acceleration_unit_rpm2 omitted: the Unit column of Profile Acceleration "
                                  f"('{item.unit}') is not in rev/min²")
                return
            m["acceleration_unit_rpm2"] = float(mt.group(1).replace(",", ""))
            self.notes.append(f"motion.acceleration_unit_rpm2: {m['acceleration_unit_rpm2']} rev/min² per unit "
                              f"(Unit column of Profile Acceleration({item.row.address}): '{item.unit}'"
                              + (", velocity-based profile" if " / " in item.unit else "") + ")")
            return
        for sec in self.page.section_for(item.row.address):
            for tab in tables_in(self.page.section_text(sec, self.ref).splitlines()):
                for cells in tab.rows:
                    if len(cells) >= 2 and clean_cell(cells[0]).lower() == "unit":
                        mt = accel.fullmatch(clean_cell(cells[1]))
                        if mt:
                            m["acceleration_unit_rpm2"] = float(mt.group(1).replace(",", ""))
                            self.notes.append(
                                f"motion.acceleration_unit_rpm2: {m['acceleration_unit_rpm2']} rev/min² per unit "
                                f"(the page's table has no Unit column; the '{tab.header[0]}' table of the Profile "
                                f"Acceleration({item.row.address}) description (control_table_profile_acceleration "
                                f"include) says 'Unit {clean_cell(cells[1])}')")
                            return
        self.notes.append("motion.acceleration_unit_rpm2 omitted: no rev/min² unit is stated for Profile "
                          "Acceleration")

    def indirect(self) -> list[dict] | None:
        ind = [i for i in self.items if i.key.startswith("indirect_")]
        if not ind:
            return None
        fam = self.fw_family if self.fw_family in INDIRECT_BLOCKS else self.family
        blocks = INDIRECT_BLOCKS[fam]
        expected = set()
        out = []
        for first, last, addr0, data0 in blocks:
            for n in range(first, last + 1):
                a = self.by_key.get(f"indirect_address_{n}")
                d = self.by_key.get(f"indirect_data_{n}")
                if not a or a.row.address != addr0 + 2 * (n - first) or a.row.size != 2:
                    raise ValueError(f"{self.name}: Indirect Address {n} not at {addr0 + 2 * (n - first)}")
                if not d or d.row.address != data0 + (n - first) or d.row.size != 1:
                    raise ValueError(f"{self.name}: Indirect Data {n} not at {data0 + (n - first)}")
                expected |= {a.key, d.key}
            out.append({"address": addr0, "data": data0, "count": last - first + 1})
        extra = {i.key for i in ind} - expected
        if extra:
            raise ValueError(f"{self.name}: indirect items outside the expected blocks: {sorted(extra)}")
        self.notes.append("indirect: " + ", ".join(
            f"Indirect Address {f} ~ {l} at {a} ~ {a + 2 * (l - f)}, Data at {d} ~ {d + (l - f)}"
            for f, l, a, d in blocks) + " (elided rows expanded; counts match the page and README)")
        return out

    def protocols(self) -> list[int]:
        fam = self.family
        if fam in V1_FAMILIES:
            return [1]
        if fam in ("x", "mx2") and self.name not in X330:
            self.notes.append("protocols: 2.0 by default, 1.0 through Protocol Type(13) = 1")
            return [2, 1]
        if self.name in X330:
            self.notes.append("protocols: 2.0 only; Protocol Type 20/21/22 select RC receiver protocols "
                              "(S.BUS, iBUS, RC-PWM), which are not DYNAMIXEL bus protocols")
        if fam == "p":
            self.notes.append("protocols: 2.0 only; Protocol Type 10 (Modbus-RTU) is accepted by the item but "
                              "is not a DYNAMIXEL protocol and is not listed")
        return [2]

    def source(self) -> str:
        head = "\n".join(self.page.lines[:15])
        m = re.search(r"(?:Text below taken from|e-Manual source):\s*(ROBOTIS-GIT/\w+) `([^`]+)`"
                      r"(?:[^\n]*?(?:commit|@) ([0-9a-f]{40}))?", head)
        if not m:
            raise ValueError(f"{self.name}: page header names no source")
        src = f"{m.group(1)} {m.group(2)}"
        if m.group(3):
            src += f" @ {m.group(3)}"
        return f"control-tables/{self.name}.md ({src})"

    def title(self) -> str:
        """models.tsv's model name as ROBOTIS prints it ('MX-28', 'MX-28(2.0)', 'H54-200-S500-R')."""
        t = self.tsv["model"]
        if "(1.0)" in t or "(legacy PRO)" in t:
            t = t.replace(" (legacy PRO)", "").replace("(1.0)", "")
            self.notes.append(f"title: '{t}' as the page prints it; models.tsv's '{self.tsv['model']}' adds a "
                              f"qualifier that the name field already carries")
        return t

    # -- all together ---------------------------------------------------------------------------

    def build(self) -> dict:
        fw, fw_note = FIRMWARE[self.fw_family]
        self.make_items()
        self.printed_ranges()
        self.fill_unprinted_ranges()
        self.signedness()
        self.operating_modes()
        self.protocol_type_values()
        self.baud_rate_values()
        self.resolve_limits()
        self.initial_values(fw)
        self.secondary_id_range()
        self.angle_limit_note()
        self.mx2_profile_limit()
        self.check_description_agreement()

        model_number = self.by_key["model_number"].initial
        if str(model_number) != self.tsv["model_number"]:
            raise ValueError(f"{self.name}: model number {model_number} != models.tsv {self.tsv['model_number']}")
        self.notes.insert(0, fw_note)
        rates, default_baud = self.baud_rates()
        timing = dict(TIMING_V1 if self.family in ("ax", "rx", "ex") else TIMING_OTHER, boot_ms=BOOT_MS)
        if self.family in ("ax", "rx", "ex"):
            self.notes.append("timing: ping 18 us, read 22 us, write 24 us + 6 us per data byte, as measured on an "
                              "AX-12 (figures given with the converter's brief); used for RX and EX as the same "
                              "Protocol 1.0 generation")
        else:
            self.notes.append("timing: 50 us for ping, read and write, none per byte ('MX about 50 us'); the same "
                              "figure is used for X, XL-320, P and PRO, for which nothing is measured")
        self.notes.append(BOOT_NOTE)
        self.notes.append("return_delay_unit_us: 2 (Return Delay Time include: 'its unit is 2 [usec]')")
        default_id = 1
        if self.name == "2xl430-w250":
            self.notes.append("default_id: 1 for the first axis; the second axis of the module is ID 2 "
                              "(ID(7) initial '1, 2')")
        model = {
            "name": self.name, "title": self.title(), "model_number": model_number,
            "firmware_version": fw, "family": self.family, "protocols": self.protocols(),
            "default_id": default_id, "baud_rates": rates, "default_baud_index": default_baud,
            "return_delay_unit_us": 2, "timing": timing, "motion": self.motion(),
        }
        ind = self.indirect()
        if ind:
            model["indirect"] = ind
        if self.name == "2xl430-w250":
            model["axes"] = 2
            model["shared_items"] = ["baud_rate", "protocol_type"]
            self.notes.append("axes: two axes, each with this control table; Baud Rate(8) and Protocol Type(13) are "
                              "shared ('Attempting to change the Baud Rate of one joint will also affect the other "
                              "joint'); EEPROM is writable only while both axes have Torque Enable 0 (README 16)")
        model["source"] = self.source()
        model["notes"] = self.notes
        model["items"] = [i.to_json() for i in sorted(self.items, key=lambda i: i.row.address)]
        return model

    def secondary_id_range(self):
        """X/MX(2.0) print 0 ~ 252 for Secondary ID but ship it as 255 (= function off)."""
        item = self.by_key.get("secondary_id")
        if item is None or item.max is None or item.initial <= item.max:
            return
        item.notes.append(f"range: {item.min} ~ {item.max} is printed but the factory value is {item.initial}; "
                          f"the Secondary ID include says '0 ~ 252 Activate Secondary ID function, 253 ~ 255 "
                          f"Deactivate Secondary ID function, Default value 255' ({EMANUAL_INCLUDES}"
                          f"control_table_shadowid.md, not in the reference), so 0 ~ 255 is accepted")
        item.max = 255

    def angle_limit_note(self):
        """AX/RX/EX/MX 1.0 and XL-320: CW/CCW Angle Limit bound Goal Position only in joint mode."""
        if self.family not in V1_FAMILIES and self.family != "xl320":
            return
        item = self.by_key["goal_position"]
        multi = ", or multi-turn mode (both 4,095)" if self.family == "mx1" else ""
        item.notes.append("limits: CW/CCW Angle Limit(6, 8) bound Goal Position in joint mode only, and a goal "
                          "outside them raises the Angle Limit Error bit rather than a range error; they do not "
                          f"apply in wheel mode (both 0){multi}. limit_min/limit_max cannot express a "
                          "mode-dependent bound, so none is set and the family code applies the rule (README 32)")

    def mx2_profile_limit(self):
        """MX(2.0): Profile Acceleration may not exceed Acceleration Limit(40) (acclimit include)."""
        if self.family != "mx2":
            return
        item, lim = self.by_key["profile_acceleration"], self.by_key["acceleration_limit"]
        item.limit_max = "acceleration_limit"
        item.notes.append("limit_max: acceleration_limit: 'Profile Acceleration(108) can't be configured with any "
                          f"values exceeding Acceleration Limit(40)' ({EMANUAL_INCLUDES}control_table_acclimit.md, "
                          "not in the reference)")
        item.max = min(item.max, lim.max)

    def check_description_agreement(self):
        """Where both the table and a description table state a range, record disagreements."""
        for item in self.items:
            if item.range_from != "table":
                continue
            for spec in self.section_ranges(item):
                if spec.min is not None and spec.max is not None and (spec.min, spec.max) != (item.min, item.max) \
                        and not spec.extra and len(self.page.section_for(item.row.address)) == 1:
                    sec = self.page.section_for(item.row.address)[0]
                    if len(sec.addresses) == 1:
                        item.notes.append(f"range: the table's {item.min} ~ {item.max} is used; the description "
                                          f"section says '{spec.raw}' (the page disagrees with itself)")


def parse_bps(text: str) -> int | None:
    t = text.replace("[bps]", "").replace("bps", "").replace(",", "").strip()
    m = re.fullmatch(r"([\d.]+)\s*(M|Mbps|K)?", t.replace(" ", ""))
    if not m:
        return None
    n = float(m.group(1))
    mult = {"M": 1e6, "Mbps": 1e6, "K": 1e3, None: 1}[m.group(2)]
    return int(round(n * mult))


@dataclass
class PageSpec:
    """Motor figures read from a page's Specifications table (see parse_spec_table)."""
    rpm: float
    nm: float
    amps: float | None
    volts: float | None
    detail: str
    torque_text: str
    speed_text: str


def parse_spec_table(lines: list[str]) -> PageSpec | None:
    """No-load speed, stall torque and stall current, and the voltage they are stated at, from a
    Specifications table; where several voltages are listed, the recommended one."""
    rows = {}
    for tab in tables_in(lines):
        if tab.header and tab.header[0].lower().startswith("item"):
            for cells in tab.rows:
                if len(cells) >= 2:
                    rows[clean_cell(cells[0]).lower()] = cells[1]
    if "stall torque" not in rows or "no load speed" not in rows:
        return None
    rec = re.search(r"Recommended\s*:\s*([\d.]+)", clean_cell(rows.get("input voltage", "")))
    rec_v = float(rec.group(1)) if rec else None

    def entries(cell):
        out = []
        for part in re.split(r"<br\s*/?>", cell):
            p = clean_cell(part)
            num = re.match(r"\s*([\d.]+)", p)
            volt = re.search(r"(?:at|@)\s*([\d.]+)\s*\[?V", p)
            if num:
                out.append((float(num.group(1)), float(volt.group(1)) if volt else None, p))
        return out

    torque, speed = entries(rows["stall torque"]), entries(rows["no load speed"])

    def pick(es):
        at = [e for e in es if rec_v is not None and e[1] == rec_v]
        chosen = at or es
        return chosen[0], len(chosen) > 1, chosen

    (t, _, _), (s, several, all_s) = pick(torque), pick(speed)
    detail = ""
    if several:
        detail = (f"; the page lists several no-load speeds at that voltage ({'; '.join(e[2] for e in all_s)}): "
                  f"the first, the motor's free-running speed, is used")
    elif len(torque) > 1:
        detail = "; the figure at the recommended input voltage is used"
    volts = t[1] if t[1] is not None else rec_v
    if volts is not None and rec_v is not None and volts != rec_v:
        detail += (f"; the figures are stated at {volts} V only, not at the recommended input voltage "
                   f"({rec_v} V), so nominal_voltage_v is {volts}")
    if s[1] is not None and volts is not None and s[1] != volts:
        raise ValueError(f"no-load speed stated at {s[1]} V but stall torque at {volts} V")
    # "1.5 [N.m] (at 12 [V], 1.5 [A])", "10.9 [N.m] (at 18.5V, 7A)", "6.0Nm @ 12V, 4.1A" (not "[Nm/A]")
    amps = re.search(r",\s*([\d.]+)\s*\[?A\b", t[2])
    rpm = int(s[0]) if s[0].is_integer() else s[0]
    return PageSpec(rpm, t[0], float(amps.group(1)) if amps else None, volts, detail, t[2], s[2])


# ---------------------------------------------------------------------------------------------
# Validation of the produced model (the structural rules of docs/model-format.md)
# ---------------------------------------------------------------------------------------------

FAMILIES = {"x", "mx2", "mx1", "ax", "rx", "ex", "xl320", "p", "pro"}
TOP_REQUIRED = {"name": str, "title": str, "model_number": int, "firmware_version": int, "family": str,
                "protocols": list, "default_id": int, "baud_rates": list, "default_baud_index": int,
                "return_delay_unit_us": int, "timing": dict, "motion": dict, "source": str, "items": list}
MOTION_KEYS = {"degrees_per_pulse", "velocity_unit_rpm", "current_unit_ma", "no_load_speed_rpm", "stall_torque_nm",
               "stall_current_a", "nominal_voltage_v", "acceleration_unit_rpm2"}
ITEM_KEYS = {"key", "name", "address", "size", "access", "area", "initial", "initial_from", "signed", "min",
             "max", "values", "limit_min", "limit_max", "unit", "note"}


def validate(model: dict) -> None:
    """Raise AssertionError naming the model and the rule broken."""
    name = model.get("name", "?")

    def need(cond, msg):
        if not cond:
            raise AssertionError(f"{name}: {msg}")

    for k, t in TOP_REQUIRED.items():
        need(isinstance(model.get(k), t) and not isinstance(model.get(k), bool), f"{k} missing or not {t.__name__}")
    need(model["family"] in FAMILIES, "unknown family")
    need(0 <= model["model_number"] <= 65535, "model_number out of 0 ~ 65535")
    need(0 <= model["firmware_version"] <= 255, "firmware_version out of 0 ~ 255")
    need(model["protocols"] and set(model["protocols"]) <= {1, 2}, "protocols")
    idx = [b["index"] for b in model["baud_rates"]]
    need(len(idx) == len(set(idx)), "duplicate baud index")
    need(model["default_baud_index"] in idx, "default baud index not in baud_rates")
    for k in ("ping_us", "read_us", "write_us", "write_per_byte_us", "boot_ms"):
        need(isinstance(model["timing"].get(k), int), f"timing.{k}")
    for k in ("degrees_per_pulse", "velocity_unit_rpm"):
        need(isinstance(model["motion"].get(k), (int, float)), f"motion.{k}")
    need(set(model["motion"]) <= MOTION_KEYS, f"motion: unknown fields {set(model['motion']) - MOTION_KEYS}")
    for k, v in model["motion"].items():
        need(isinstance(v, (int, float)) and not isinstance(v, bool) and v > 0, f"motion.{k} not a positive number")
    items = model["items"]
    keys, addrs, occupied = set(), set(), {}
    by_key = {i["key"]: i for i in items}
    for it in items:
        k = it["key"]
        need(set(it) <= ITEM_KEYS, f"{k}: unknown fields {set(it) - ITEM_KEYS}")
        need(re.fullmatch(r"[a-z0-9_]+", k) is not None, f"{k}: key not snake_case")
        need(k not in keys, f"duplicate key {k}")
        need(it["address"] not in addrs, f"duplicate address {it['address']}")
        keys.add(k)
        addrs.add(it["address"])
        need(it["size"] in (1, 2, 4), f"{k}: size {it['size']}")
        need(it["access"] in ("R", "RW") and it["area"] in ("EEPROM", "RAM"), f"{k}: access/area")
        for a in range(it["address"], it["address"] + it["size"]):
            need(a not in occupied, f"{k} overlaps {occupied.get(a)}")
            occupied[a] = k
        need(("initial" in it) != ("initial_from" in it), f"{k}: exactly one of initial / initial_from")
        lo, hi = full_width(it["size"], it.get("signed", False))
        lo, hi = it.get("min", lo), it.get("max", hi)
        need(("min" in it) == ("max" in it), f"{k}: min without max")
        need(lo <= hi, f"{k}: min > max")
        need(full_width(it["size"], it.get("signed", False))[0] <= lo and
             hi <= full_width(it["size"], it.get("signed", False))[1], f"{k}: range exceeds the item width")
        if "initial" in it:
            need(isinstance(it["initial"], int), f"{k}: initial not an integer")
            need(lo <= it["initial"] <= hi, f"{k}: initial {it['initial']} outside {lo} ~ {hi}")
            if "values" in it:
                need(it["initial"] in it["values"], f"{k}: initial not in values")
        else:
            need(it["initial_from"] in by_key, f"{k}: initial_from names no item")
        for side in ("limit_min", "limit_max"):
            if side in it:
                need(it[side].lstrip("-") in by_key, f"{k}: {side} names no item")
    for it in items:
        if "initial_from" in it:
            src = by_key[it["initial_from"]]
            lo, hi = it.get("min", full_width(it["size"], False)[0]), it.get("max", full_width(it["size"], False)[1])
            need("initial" in src and lo <= src["initial"] <= hi, f"{it['key']}: initial_from value outside range")
    for blk in model.get("indirect", []):
        for i in range(blk["count"]):
            a = next((x for x in items if x["address"] == blk["address"] + 2 * i), None)
            d = next((x for x in items if x["address"] == blk["data"] + i), None)
            need(a is not None and a["size"] == 2 and a["key"].startswith("indirect_address_"),
                 f"indirect block {blk}: address entry {i}")
            need(d is not None and d["size"] == 1 and d["key"].startswith("indirect_data_"),
                 f"indirect block {blk}: data entry {i}")
    if "axes" in model:
        need(model["axes"] == 2 and all(k in by_key for k in model.get("shared_items", [])), "axes/shared_items")


# ---------------------------------------------------------------------------------------------
# Cross-check against the printed tables
# ---------------------------------------------------------------------------------------------

def cross_check(page: Page, model: dict) -> list[str]:
    """Every printed row appears as an item with the same identity; nothing extra.

    Returns the list of documented deviations (each carries a note in the item); raises on
    anything undocumented.
    """
    items = {i["address"]: i for i in model["items"]}
    problems, deviations = [], []
    if len(items) != len(page.rows):
        problems.append(f"{len(items)} items for {len(page.rows)} rows")
    for row in page.rows:
        it = items.get(row.address)
        if it is None:
            problems.append(f"row {row.name}({row.address}) has no item")
            continue
        if (it["name"], it["size"], it["area"]) != (row.name, row.size, row.area):
            problems.append(f"{row.name}: name/size/area differ")
        if it["access"] != row.access:
            if row.access == "R/RW" and "note" in it:
                deviations.append(f"{it['key']}: access R/RW -> RW")
            else:
                problems.append(f"{row.name}: access {it['access']} != {row.access}")
        n = parse_int(row.initial)
        if n is not None and it.get("initial") != n:
            problems.append(f"{row.name}: initial {it.get('initial')} != printed {n}")
        spec = None
        if row.minmax is not None:
            lo, hi = (parse_int(x) for x in row.minmax)
            if lo is not None:
                spec = RangeSpec(min=lo, max=hi)
        elif "range" in page.columns:
            spec = parse_range(row.range)
        if spec is None:
            continue
        if spec.values is not None and len(spec.values) > 1:
            if it.get("values") != spec.values:
                problems.append(f"{row.name}: values {it.get('values')} != printed {spec.values}")
            continue
        if spec.min is not None and it.get("min") != spec.min:
            if "note" in it and "range" in it["note"]:
                deviations.append(f"{it['key']}: min {spec.min} -> {it.get('min')}")
            else:
                problems.append(f"{row.name}: min {it.get('min')} != printed {spec.min}")
        if spec.max is not None and it.get("max") != spec.max:
            if "note" in it and "range" in it["note"]:
                deviations.append(f"{it['key']}: max {spec.max} -> {it.get('max')}")
            else:
                problems.append(f"{row.name}: max {it.get('max')} != printed {spec.max}")
        for side, ref in (("limit_min", spec.lo_ref), ("limit_max", spec.hi_ref)):
            if ref and it.get(side, "").lstrip("-") != snake_key(ref[1]):
                problems.append(f"{row.name}: {side} {it.get(side)} != printed {ref}")
    if problems:
        raise AssertionError(f"{page.name}: cross-check failed:\n  " + "\n  ".join(problems))
    return deviations


# ---------------------------------------------------------------------------------------------
# Output
# ---------------------------------------------------------------------------------------------

def dump(obj) -> str:
    return json.dumps(obj, indent=2, ensure_ascii=False) + "\n"


def build_all(ref: Reference, quiet: bool) -> dict[str, str]:
    """All output files as {file name: text}."""
    available = set(ref.page_names())
    missing = [name for name in CONVERTED_PAGES if name not in available]
    if missing:
        raise SystemExit(f"convert_models: no page for {', '.join(missing)} in {ref.pages_dir}")
    pages = {name: read_page(ref, name) for name in CONVERTED_PAGES}
    donors = {"xm430-w350": pages["xm430-w350"], "xl430-w250": pages["xl430-w250"]}
    files, catalog, summary = {}, [], []
    for name, page in pages.items():
        try:
            model = ModelBuilder(ref, page, donors).build()
            validate(model)
            deviations = cross_check(page, model)
        except (ValueError, AssertionError, KeyError) as exc:
            raise SystemExit(f"convert_models: {name}: {exc}")
        files[f"{name}.json"] = dump(model)
        catalog.append({"name": name, "title": model["title"], "model_number": model["model_number"],
                        "family": model["family"], "protocols": model["protocols"], "file": f"{name}.json"})
        n_notes = len(model["notes"]) + sum(1 for i in model["items"] if "note" in i)
        summary.append((name, model["family"], len(model["items"]), len(model["notes"]), n_notes, deviations))
    files["catalog.json"] = dump({"models": sorted(catalog, key=lambda c: c["name"])})
    if not quiet:
        print(f"{'model':<18} {'family':<6} {'items':>5} {'model notes':>11} {'all notes':>9}  documented deviations")
        for name, fam, n_items, n_mnotes, n_notes, dev in summary:
            print(f"{name:<18} {fam:<6} {n_items:>5} {n_mnotes:>11} {n_notes:>9}  {', '.join(dev) or '-'}")
        fams = {}
        for _, fam, *_ in summary:
            fams[fam] = fams.get(fam, 0) + 1
        print("per family: " + ", ".join(f"{f} {n}" for f, n in sorted(fams.items())))
    return files


def print_not_converted(ref: Reference) -> None:
    """Names the reference pages that no model is made from (CONVERTED_PAGES)."""
    rest = sorted(set(ref.page_names()) - set(CONVERTED_PAGES))
    if rest:
        print(f"not converted: {len(rest)} reference pages have no model yet: {', '.join(rest)}")


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--reference", type=Path, default=DEFAULT_REFERENCE,
                    help="reference directory (default: ../shared/reference from the repository root)")
    ap.add_argument("--out", type=Path, default=DEFAULT_OUT, help="output directory (default: models/)")
    ap.add_argument("--check", action="store_true",
                    help="write nothing; exit 1 listing files that differ from what is in --out")
    ap.add_argument("--quiet", action="store_true", help="no per-model summary")
    args = ap.parse_args(argv)
    files = build_all(Reference(args.reference), args.quiet or args.check)
    out: Path = args.out
    if args.check:
        differ = [f for f, text in sorted(files.items())
                  if not (out / f).exists() or (out / f).read_text(encoding="utf-8") != text]
        stale = sorted(p.name for p in out.glob("*.json") if p.name not in files)
        for f in differ:
            print(f"differs: {out / f}")
        for f in stale:
            print(f"not generated (stale): {out / f}")
        if differ or stale:
            print("run: python3 scripts/convert_models.py")
            return 1
        print(f"models: {len(files)} files up to date")
        print_not_converted(Reference(args.reference))
        return 0
    out.mkdir(parents=True, exist_ok=True)
    for f, text in sorted(files.items()):
        path = out / f
        if not path.exists() or path.read_text(encoding="utf-8") != text:
            path.write_text(text, encoding="utf-8")
    return 0


if __name__ == "__main__":
    sys.exit(main())
