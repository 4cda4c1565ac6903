"""Motor figures for models whose page has no Specifications table, read from public e-Manual
sources (each with its URL and the text quoted)."""

from __future__ import annotations

from dataclasses import dataclass

# Motor specifications read from public e-Manual sources (the offline copies omit most
# specification sections), for models whose page has no Specifications table that spec_table.py
# reads (none, or one without a No Load Speed or Stall Torque row). Figures at the
# voltage named (the recommended input voltage unless the source says otherwise); None where the
# source states no such figure, and `missing` then says why. Models not listed and without a
# specification table on their page get no no_load_speed_rpm / stall_torque_nm / stall_current_a.
#
# Where an English page could not be read, the figures come from the e-Manual's own data files:
# `_data/dxl_x_info.yml` / `_data/dxl_mx_info.yml` of ROBOTIS-GIT/emanual hold the `stalltorque` and
# `noloadspeed` strings that `_includes/en/dxl/specifications_x.md` renders, per page `ref`, as the
# page's Specifications table (the figure at the recommended voltage is printed in bold there);
# `dxl_p_info.yml`, `dxl_pro_info.yml`, `dxl_proa_info.yml`, `dxl_y_info.yml` and `rh_p12_rn_info.yml` do
# the same for the P, PRO, PRO(A) and Y pages and the grippers (`noloadspeed`, `opvoltage`, and the
# continuous `contspeed` / `conttorque` / `contcurrent`, which are not stall figures).
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


# The X pages added after that dxl_x_info.yml revision (XD, XW430, XW540-H260, XM335, XC430-T*BB) are read from
# ROBOTIS's Docusaurus migration of the e-Manual, whose model_reference pages carry the Specifications table inline
# (rendered from a newer dxl_x_info.yml; the figure at the recommended voltage is bold there too).
DOCS_X_PAGES = ("https://github.com/ROBOTIS-GIT/docs/blob/082d60e95a1add51db323656d2bedd0e015e7881/"
                "docusaurus/docs/dxl/model_reference/x_series/")
EMANUAL_P_INFO = ("https://github.com/ROBOTIS-GIT/emanual/blob/1a5e5fbeb6c41e261a1c67ba74e1cb3ec728072e/"
                  "_data/dxl_p_info.yml")
EMANUAL_PRO_INFO = ("https://github.com/ROBOTIS-GIT/emanual/blob/0b368d95abbd269e7ce1bbbbf20549e239b11091/"
                    "_data/dxl_pro_info.yml")
EMANUAL_PROA_INFO = ("https://github.com/ROBOTIS-GIT/emanual/blob/15d20230297622826783f4f6e4687c0777bcbb8a/"
                     "_data/dxl_proa_info.yml")
EMANUAL_Y_INFO = ("https://github.com/ROBOTIS-GIT/emanual/blob/72b855d7037e47f9ba3e7b80d8192bd14d252181/"
                  "_data/dxl_y_info.yml")
EMANUAL_RH_INFO = ("https://github.com/ROBOTIS-GIT/emanual/blob/29bb55c4ac96ee9827955ad46f7f43827a61ed5e/"
                   "_data/rh_p12_rn_info.yml")


def docs_page(path: str, torque: str, speed: str, voltage: str) -> str:
    """Source text for figures read from a Specifications table of ROBOTIS-GIT/docs (path under x_series/)."""
    return (f"{DOCS_X_PAGES}{path}, Specifications table: Stall Torque '{torque}', No Load Speed '{speed}', "
            f"Input Voltage '{voltage}'")


def continuous_only(contspeed: str, conttorque: str, contcurrent: str, peak: str = "") -> str:
    """Why a model whose data states only a no-load speed and a continuous operating point has no stall figures;
    `peak` quotes a maximum (peak) rating where the source gives one."""
    peak_text = (f", and a peak rating ({peak}) that the source does not state as a stall (locked-rotor) figure "
                 f"at the input voltage" if peak else "")
    return (f"stall_torque_nm and stall_current_a omitted: the e-Manual states no stall torque or stall current for "
            f"this model, only the no-load speed and the continuous (rated) operating point (contspeed "
            f"'{contspeed}', conttorque '{conttorque}', contcurrent '{contcurrent}'), which is a rated load, not a "
            f"stall{peak_text}; no stated stall figure was found elsewhere")


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
    # X pages read from dxl_x_info.yml (the figure at the recommended voltage, bold in the data where marked)
    "2xc430-w250": MotorSpec(64, 1.8, 1.4, 12.0, x_info(
        "2xc430-w250", "**1.8 [N.m] (at 12.0 [V], 1.4 [A])**", "**64 [rev/min] (at 12.0 [V])**",
        "https://emanual.robotis.com/docs/en/dxl/x/2xc430-w250/") + "; voltage_en '6.5 ~ 14.8 [V] (**Recommended : "
        "12.0 [V]**)'; the figures are per axis (each axis is one motor)"),
    "xc330-m181": MotorSpec(129, 0.60, 1.80, 5.0, x_info(
        "xc330-m181", "**0.60 [N.m] (at 5.0 [V], 1.80 [A])**", "**129 [rev/min] (at 5.0 [V])**",
        "https://emanual.robotis.com/docs/en/dxl/x/xc330-m181/") + "; voltage_en '3.7 ~ 6.0 [V] (**Recommended : "
        "5.0 [V]**)'; the rendered page https://emanual.robotis.com/docs/en/dxl/x/xc330-m181/ prints the same "
        "('0.60 [N.m] (at 5.0 [V], 1.80 [A])', '129 [rev/min] (at 5.0 [V])')"),
    "xc330-m288": MotorSpec(81, 0.93, 1.80, 5.0, x_info(
        "xc330-m288", "**0.93 [N.m] (at 5.0 [V], 1.80 [A])**", "**81 [rev/min] (at 5.0 [V])**",
        "https://emanual.robotis.com/docs/en/dxl/x/xc330-m288/") + "; voltage_en '3.7 ~ 6.0 [V] (**Recommended : "
        "5.0 [V]**)'; the rendered page https://emanual.robotis.com/docs/en/dxl/x/xc330-m288 prints the same "
        "('0.93 [N.m] (at 5.0 [V], 1.80 [A], 0.517 [Nm/A])', '81 [rev/min] (at 5.0 [V])'). The e-Manual's "
        "form-factor table _includes/common/compatible_dxl/compatible_x330.md (at b0f9fcc7) prints '0.215 [N.m] "
        "(at 5.0 [V], 1.47 [A])' for XC330-M288, the XL330-M077 row copied; not used"),
    "xc330-t181": MotorSpec(104, 0.76, 0.80, 11.1, x_info(
        "xc330-t181", "**0.76 [N.m] (at 11.1 [V], 0.80 [A])**", "**104 [rev/min] (at 11.1 [V])**",
        "https://emanual.robotis.com/docs/en/dxl/x/xc330-t181/") + "; voltage_en '6.5 ~ 12.0 [V] (**Recommended : "
        "11.1 [V]**)'; the Korean page https://emanual.robotis.com/docs/kr/dxl/x/xc330-t181/ prints the same "
        "('0.76 [N.m] (at 11.1 [V], 0.80 [A])', '104 [rev/min] (at 11.1 [V])', '권장 전압 : 11.1 [V]')"),
    "xh430-v210": MotorSpec(52, 2.6, 0.7, 24.0, x_info(
        "xh430-v210", "2.6 [N.m] (at 24 [V], 0.7[A])", "52 [rev/min] (at 24 [V])",
        "https://emanual.robotis.com/docs/en/dxl/x/xh430-v210/") + "; one voltage only, voltage_en '24.0 [V] "
        "(**Recommended : 24.0 [V]**)'; the Korean page https://emanual.robotis.com/docs/kr/dxl/x/xh430-v210 "
        "prints '2.6 [N.m] (at 24 [V], 0.7 [A], 3.714 [Nm/A])', '52 [rev/min] (at 24 [V])'"),
    "xh430-v350": MotorSpec(31, 3.3, 0.7, 24.0, x_info(
        "xh430-v350", "3.3 [N.m] (at 24 [V], 0.7[A])", "31 [rev/min] (at 24 [V])",
        "https://emanual.robotis.com/docs/en/dxl/x/xh430-v350/") + "; one voltage only, voltage_en '24.0 [V] "
        "(**Recommended : 24.0 [V]**)'"),
    "xh540-v150": MotorSpec(60, 6.4, 2.4, 24.0, x_info(
        "xh540-v150", "6.4 [N.m] (at 24 [V], 2.4 [A])", "60 [rev/min] (at 24 [V])",
        "https://emanual.robotis.com/docs/en/dxl/x/xh540-v150/") + "; one voltage only, voltage_en '24.0 [V] "
        "(**Recommended : 24.0 [V]**)'; the rendered page https://emanual.robotis.com/docs/en/dxl/x/xh540-v150 "
        "prints '6.4 [N.m] (at 24 [V], 2.4 [A], 2.667 [Nm/A])', '60 [rev/min] (at 24 [V])'"),
    "xh540-v270": MotorSpec(34, 9.2, 2.4, 24.0, x_info(
        "xh540-v270", "9.2 [N.m] (at 24 [V], 2.4 [A])", "34 [rev/min] (at 24 [V])",
        "https://emanual.robotis.com/docs/en/dxl/x/xh540-v270/") + "; one voltage only, voltage_en '24.0 [V] "
        "(**Recommended : 24.0 [V]**)'; the rendered page https://emanual.robotis.com/docs/en/dxl/x/xh540-v270 "
        "prints '9.2 [N.m] (at 24 [V], 2.4 [A], 3.833 [Nm/A])', '34 [rev/min] (at 24 [V])'"),
    "xw540-t140": MotorSpec(72, 6.9, 4.9, 12.0, x_info(
        "xw540-t140", "**6.9 [N.m] (at 12.0 [V], 4.9 [A])**", "**72 [rev/min] (at 12.0 [V]**",
        "https://emanual.robotis.com/docs/en/dxl/x/xw540-t140/") + "; voltage_en '10.0 ~ 14.8 [V] (**Recommended : "
        "12.0 [V]**)'; the rendered page https://emanual.robotis.com/docs/en/dxl/x/xw540-t140 prints '6.9 [N.m] "
        "(at 12.0 [V], 4.9 [A], 1.408 [Nm/A])', '72 [rev/min] (at 12.0 [V]'"),
    # X pages read from the Specifications tables of ROBOTIS-GIT/docs
    "xd430-t210": MotorSpec(50, 2.5, 1.3, 12.0, docs_page(
        "xd_series/xd430-t210.mdx", "**2.5 [N.m] (at 12.0 [V], 1.3 [A], 1.923 [Nm/A])**",
        "**50 [rev/min] (at 12.0 [V])**", "10.0 ~ 14.8 [V] (**Recommended : 12.0 [V]**)")
        + "; the same as XH430-W210, whose 'improved lifespan version' the page says XD430 is"),
    "xd430-t350": MotorSpec(30, 3.4, 1.3, 12.0, docs_page(
        "xd_series/xd430-t350.mdx", "**3.4 [N.m] (at 12.0 [V], 1.3 [A], 2.615 [Nm/A])**",
        "**30 [rev/min] (at 12.0 [V])**", "10.0 ~ 14.8 [V] (**Recommended : 12.0 [V]**)")),
    "xd540-t150": MotorSpec(70, 7.1, 4.9, 12.0, docs_page(
        "xd_series/xd540-t150.mdx", "7.1 [N.m] (at 12.0 [V], 4.9 [A], 1.449 [Nm/A])",
        "70 [rev/min] (at 12.0 [V])", "10.0 ~ 14.8 [V] (**Recommended : 12.0 [V]**)")
        + "; no figure is bold on this page (as for XH540-W150), so the row at the recommended voltage is used"),
    "xd540-t270": MotorSpec(39, 9.9, 4.9, 12.0, docs_page(
        "xd_series/xd540-t270.mdx", "**9.9 [N.m] (at 12.0 [V], 4.9 [A], 2.020 [Nm/A])**",
        "**39 [rev/min] (at 12.0 [V])**", "10.0 ~ 14.8 [V] (**Recommended : 12.0 [V]**)")),
    "xw430-t200": MotorSpec(53, 2.3, 1.3, 12.0, docs_page(
        "xw_series/xw430-t200.mdx", "**2.3 [N.m] (at 12.0 [V], 1.3 [A], 1.769 [Nm/A])**",
        "**53 [rev/min] (at 12.0 [V])**", "10.0 ~ 14.8 [V] (**Recommended : 12.0 [V]**)")
        + ". The e-Manual's form-factor table (ROBOTIS-GIT/emanual _includes/common/compatible_dxl/"
        "compatible_x430.md at f7e8795a, and its Docusaurus copy) prints '6.9 [N.m] (at 12.0 [V], 4.9 [A])' for "
        "XW430-T200-R: the XW540-T140 torque row copied (this model's Current Limit, 648 x 2.69 mA = 1.74 A, "
        "cannot reach 4.9 A); not used"),
    "xw430-t333": MotorSpec(31, 3.1, 1.3, 12.0, docs_page(
        "xw_series/xw430-t333.mdx", "**3.1 [N.m] (at 12.0 [V], 1.3 [A], 2.385 [Nm/A])**",
        "**31 [rev/min] (at 12.0 [V])**", "10.0 ~ 14.8 [V] (**Recommended : 12.0 [V]**)")),
    "xw540-h260": MotorSpec(32, 8.7, 2.4, 24.0, docs_page(
        "xw_series/xw540-h260.mdx", "8.7 [N.m] (at 24 [V], 2.4 [A], 3.625 [Nm/A])", "32 [rev/min] (at 24 [V])",
        "24.0 [V] (**Recommended : 24.0 [V]**)") + "; one voltage only"),
    "xm335-t323": MotorSpec(53, 1.03, 0.80, 11.1, docs_page(
        "xm_series/xm335-t323.mdx", "**1.03 [N.m] (at 11.1 [V], 0.80[A], 1.290 [N.m/A])**",
        "**53 [rev/min] (at 11.1 [V])**", "6.5 ~ 12.0 [V] (**Recommended : 11.1 [V]**)")),
    "xc430-t150bb": MotorSpec(106, 1.6, 1.4, 12.0, docs_page(
        "xc_series/xc430-t150bb.mdx", "**1.6 [N.m] (at 12.0 [V], 1.4 [A], 1.143 [Nm/A])**",
        "**106 [rev/min] (at 12.0 [V])**", "6.5 ~ 14.8 [V] (**Recommended : 12.0 [V]**)")
        + "; the same as XC430-W150 ('Other specifications are the same as the existing XC430 series')"),
    "xc430-t240bb": MotorSpec(70, 1.9, 1.4, 12.0, docs_page(
        "xc_series/xc430-t240bb.mdx", "**1.9 [N.m] (at 12.0 [V], 1.4 [A], 1.357 [Nm/A])**",
        "**70 [rev/min] (at 12.0 [V])**", "6.5 ~ 14.8 [V] (**Recommended : 12.0 [V]**)")
        + "; the same as XC430-W240 ('Other specifications are the same as the existing XC430 series')"),
    # Protocol 1.0 pages whose Specifications table lacks a figure parse_spec_table needs
    "mx-12w": MotorSpec(470, 0.2, 1.4, 12.0, "https://emanual.robotis.com/docs/en/dxl/mx/mx-12w ('Stall Torque | "
                        "0.2 [N.m] (at 12.0 [V], 1.4 [A])', 'No Load Speed | 470 [rev/min] (at 12.0 [V])', "
                        "'Input Voltage | 10.0 ~ 14.8 [V] (Recommended : 12.0 [V])'; the Korean page "
                        "https://emanual.robotis.com/docs/kr/dxl/mx/mx-12w prints the same). An older source, "
                        "ROBOTIS-GIT/emanual docs/en/dxl/mx/mx-12w.md at 05231145, has 'No Load Speed | 470rpm "
                        "(at 12V)' and 'Input Voltage | 10 ~ 14.8V (**Recommended : 12V**)' but no Stall Torque row"),
    "dx-116": MotorSpec(None, 2.1, None, 12.0, "https://emanual.robotis.com/docs/en/dxl/dx/dx-116/ "
                        "(ROBOTIS-GIT/emanual docs/en/dxl/dx/dx-116.md at 07a99125, and this reference page's own "
                        "Specifications table: 'Stall Torque | 2.1 N&#42;m (at 12V), 2.9 N&#42;m(at 16V)', "
                        "'Input Voltage | 12 ~ 16V (**Recommended : 14.8V**)'); no figure is stated at the "
                        "recommended 14.8 V, so the 12 V one is used and nominal_voltage_v is 12.0",
                        missing="no_load_speed_rpm and stall_current_a omitted: the page states no no-load speed "
                        "and no stall current (its table has no No Load Speed row, so parse_spec_table does not "
                        "read it); ROBOTIS's 2004 DX-116 user manual (Tribotix translation, e.g. "
                        "http://www.manualsdir.com/manuals/198064/robotis-dx-116.html?page=18) says only that the "
                        "Moving Speed maximum 0x3ff 'moves at 70RPM', a joint-mode speed setting rather than a "
                        "stated no-load speed; no stated figure was found elsewhere"),
    # The grippers' pages state finger-level figures only
    "rh-p12-rn": MotorSpec(None, None, None, 24.0, f"{EMANUAL_RH_INFO}, key 'rh-p12-rn': voltage '24.0 [V]'; "
                           "https://emanual.robotis.com/docs/kr/platform/rh_p12_rn ('사용 전압 | 24V', the input "
                           "voltage)",
                           missing="no_load_speed_rpm, stall_torque_nm and stall_current_a omitted: the gripper's "
                           "specifications (https://emanual.robotis.com/docs/kr/platform/rh_p12_rn) state no motor "
                           "or output-shaft speed or torque, only finger-level figures ('최대 닫기 속도 | 75 mm/s', the "
                           "maximum closing speed; '최대 파지력 | 170 N', the maximum grip force; '감속비 | 1181 : "
                           "1', the reduction ratio; 'Peak Current | 3.33 A'); turning them into rev/min and N.m "
                           "needs the finger linkage geometry, which no source states, and the peak current is not "
                           "stated as a stall current"),
    "rh-p12-rna": MotorSpec(None, None, None, 24.0, f"{EMANUAL_RH_INFO}, key 'rh-p12-rna': voltage '24.0 [V]'; "
                            "https://emanual.robotis.com/docs/kr/platform/rh_p12_rna ('사용 전압 | 24 V', the "
                            "input voltage)",
                            missing="no_load_speed_rpm, stall_torque_nm and stall_current_a omitted: the gripper's "
                            "specifications (https://emanual.robotis.com/docs/kr/platform/rh_p12_rna) state no motor "
                            "or output-shaft speed or torque, only finger-level figures ('최대 닫기 속도 | 75 mm/s', the "
                            "maximum closing speed; '최대 파지력 | 170 N', the maximum grip force; '감속비 | 1181 "
                            ": 1', the reduction ratio; 'Peak Current | 3.33 A'); turning them into rev/min and N.m "
                            "needs the finger linkage geometry, which no source states, and the peak current is "
                            "not stated as a stall current"),
}

# Models whose data files state a no-load speed and a continuous operating point but no stall figures:
# page name -> (data file, e-Manual page folder, noloadspeed, opvoltage, contspeed, conttorque, contcurrent[, peak]),
# every string as the data file prints it.
CONTINUOUS_ONLY = {
    "ph42-020-s300-r": (EMANUAL_P_INFO, "p", "32.7 [rev/min]", "24.0 [V]", "29.2 [rev/min]", "5.1 [N.m]", "1.5 [A]"),
    "ph54-100-s500-r": (EMANUAL_P_INFO, "p", "33.3 [rev/min]", "24.0 [V]", "29.2 [rev/min]", "25.3 [N.m]", "5.5 [A]"),
    "pm42-010-s260-r": (EMANUAL_P_INFO, "p", "28.0 [rev/min]", "24.0 [V]", "26.0 [rev/min]", "1.7 [N.m]", "0.6 [A]"),
    "pm54-040-s250-r": (EMANUAL_P_INFO, "p", "28.4 [rev/min]", "24.0 [V]", "24.2 [rev/min]", "3.9 [N.m]", "1.9 [A]"),
    "pm54-060-s250-r": (EMANUAL_P_INFO, "p", "33.1 [rev/min]", "24.0 [V]", "28.3 [rev/min]", "10.1 [N.m]", "3.0 [A]"),
    "h42-20-s300-r": (EMANUAL_PRO_INFO, "pro", "32.7 [rev/min]", "24.0 [V]", "29.2 [rev/min]", "5.1 [Nm]", "1.5 [A]"),
    "h54-100-s500-r": (EMANUAL_PRO_INFO, "pro", "33.3 [rev/min]", "24.0 [V]", "29.2 [rev/min]", "25.3 [Nm]",
                       "5.5 [A]"),
    "l42-10-s300-r": (EMANUAL_PRO_INFO, "pro", "29.7 [rev/min]", "24.0 [V]", "27.9 [rev/min]", "1.2 [Nm]", "0.8 [A]"),
    "l54-30-s400-r": (EMANUAL_PRO_INFO, "pro", "28.7 [rev/min]", "24.0 [V]", "26.9 [rev/min]", "2.5 [Nm]", "1.6 [A]"),
    "l54-30-s500-r": (EMANUAL_PRO_INFO, "pro", "23.0 [rev/min]", "24.0 [V]", "21.0 [rev/min]", "5.4 [Nm]", "1.6 [A]"),
    "l54-50-s290-r": (EMANUAL_PRO_INFO, "pro", "26.0 [rev/min]", "24.0 [V]", "22.1 [rev/min]", "4.8 [Nm]", "1.9 [A]"),
    "l54-50-s500-r": (EMANUAL_PRO_INFO, "pro", "16.0 [rev/min]", "24.0 [V]", "13.7 [rev/min]", "14.0 [Nm]",
                      "1.9 [A]"),
    "m42-10-s260-r": (EMANUAL_PRO_INFO, "pro", "28.0 [rev/min]", "24.0 [V]", "26.0 [rev/min]", "1.7 [Nm]", "0.6 [A]"),
    "m54-40-s250-r": (EMANUAL_PRO_INFO, "pro", "28.4 [rev/min]", "24.0 [V]", "24.2 [rev/min]", "3.9 [Nm]", "1.9 [A]"),
    "m54-60-s250-r": (EMANUAL_PRO_INFO, "pro", "33.1 [rev/min]", "24.0 [V]", "28.3 [rev/min]", "10.1 [Nm]",
                      "3.0 [A]"),
    "h42-20-s300-ra": (EMANUAL_PROA_INFO, "pro", "32.7 [rev/min]", "24.0 [V]", "29.2 [rev/min]", "5.1 [N.m]",
                       "1.5 [A]"),
    "h54-100-s500-ra": (EMANUAL_PROA_INFO, "pro", "33.3 [rev/min]", "24.0 [V]", "29.2 [rev/min]", "25.3 [N.m]",
                        "5.5 [A]"),
    "h54-200-s500-ra": (EMANUAL_PROA_INFO, "pro", "33.1 [rev/min]", "24.0 [V]", "29.0 [rev/min]", "44.7 [N.m]",
                        "9.3 [A]"),
    "m42-10-s260-ra": (EMANUAL_PROA_INFO, "pro", "28.0 [rev/min]", "24.0 [V]", "26.0 [rev/min]", "1.7 [N.m]",
                       "0.6 [A]"),
    "m54-40-s250-ra": (EMANUAL_PROA_INFO, "pro", "28.4 [rev/min]", "24.0 [V]", "24.2 [rev/min]", "3.9 [N.m]",
                       "1.9 [A]"),
    "m54-60-s250-ra": (EMANUAL_PROA_INFO, "pro", "33.1 [rev/min]", "24.0 [V]", "28.3 [rev/min]", "10.1 [N.m]",
                       "3.0 [A]"),
}
# The Y pages add a maximum (peak) torque and current; M001 and B001 have no reducer (gear ratio '-'), so they state
# the motor's own figures.
_Y_070_MOTOR = ("5,675 [rev/min]", "4,664 [rev/min]", "0.32 [N.m]", "11.9 [A]", "0.64 [N.m]", "20.8 [A]")
_Y_070_051 = ("111.3 [rev/min]", "39.2 [rev/min]", "8.2 [N.m]", "11.9 [A]", "16.3 [N.m]", "20.8 [A]")
_Y_070_099 = ("57.3 [rev/min]", "20.2 [rev/min]", "14.6 [N.m]", "11.0 [A]", "31.7 [N.m]", "20.8 [A]")
_Y_080_MOTOR = ("3,190 [rev/min]", "2,597 [rev/min]", "0.62 [N.m]", "12.6 [A]", "1.24 [N.m]", "22.4 [A]")
_Y_080_051 = ("62.5 [rev/min]", "39.2 [rev/min]", "15.8 [N.m]", "12.6 [A]", "31.6 [N.m]", "22.4 [A]")
_Y_080_099 = ("32.2 [rev/min]", "20.2 [rev/min]", "26.0 [N.m]", "10.7 [A]", "61.4 [N.m]", "22.4 [A]")
Y_PAGES = {
    "ym070-210-m001-rh": _Y_070_MOTOR, "ym070-210-b001-rh": _Y_070_MOTOR,
    "ym070-210-r051-rh": _Y_070_051, "ym070-210-a051-rh": _Y_070_051,
    "ym070-210-r099-rh": _Y_070_099, "ym070-210-a099-rh": _Y_070_099,
    "ym080-230-m001-rh": _Y_080_MOTOR, "ym080-230-b001-rh": _Y_080_MOTOR,
    "ym080-230-r051-rh": _Y_080_051, "ym080-230-a051-rh": _Y_080_051,
    "ym080-230-r099-rh": _Y_080_099, "ym080-230-a099-rh": _Y_080_099,
}


def leading_number(text: str) -> int | float:
    """The number a data string starts with, as printed ("5,675 [rev/min]" -> 5675, "16.0 [rev/min]" -> 16.0)."""
    number = text.split()[0].replace(",", "")
    return float(number) if "." in number else int(number)


def continuous_only_specs() -> dict:
    """MotorSpec entries for the CONTINUOUS_ONLY and Y_PAGES models: the no-load speed and the voltage, with
    `missing` quoting the continuous (and peak) figures."""
    rows = dict(CONTINUOUS_ONLY)
    for key, (speed, cspeed, ctorque, ccurrent, mtorque, mcurrent) in Y_PAGES.items():
        rows[key] = (EMANUAL_Y_INFO, "y", speed, "24 [V]", cspeed, ctorque, ccurrent,
                     f"maximumtorque '{mtorque}', maximumcurrent '{mcurrent}'")
    return {key: MotorSpec(leading_number(speed), None, None, float(leading_number(volts)),
                           f"https://emanual.robotis.com/docs/en/dxl/{folder}/{key}/; {data}, key '{key}': "
                           f"noloadspeed '{speed}', opvoltage '{volts}' (the data the page's Specifications table "
                           f"is rendered from)", missing=continuous_only(*continuous))
            for key, (data, folder, speed, volts, *continuous) in rows.items()}


EXTERNAL_SPECS.update(continuous_only_specs())
