"""Motor figures for models whose page has no Specifications table, read from public e-Manual
sources (each with its URL and the text quoted)."""

from __future__ import annotations

from dataclasses import dataclass

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
    """Motor figures of one model and where they were read."""
    rpm: float | None      # no-load speed [rev/min]
    nm: float | None       # stall torque [N.m]
    amps: float | None     # stall current [A]
    volts: float           # the input voltage all three are stated at
    source: str            # where they were read (URL and the quoted text)
    missing: str = ""      # why a None figure is absent


def x_info(key: str, torque: str, speed: str, page: str) -> str:
    """Source text for figures read from the e-Manual's dxl_x_info.yml."""
    return (f"{EMANUAL_X_INFO}, key '{key}': stalltorque '{torque}', noloadspeed '{speed}' (the data the "
            f"Specifications table of {page} is rendered from)")


def mx_info(key: str, torque: str, speed: str) -> str:
    """Source text for figures read from the e-Manual's dxl_mx_info.yml."""
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
