"""Range choices, as data: ranges for items the pages leave open (the AX/RX/EX/MX 1.0 pages have
no Range column). Each entry names its evidence: a file of the reference and text that must occur
in it (checked at every run), or a public URL for includes that were not copied."""

from __future__ import annotations

from ..ranges import rc
from . import EMANUAL_INCLUDES

LEGACY = "control-tables/includes/ax-legacy-page-description-sections.md"


RANGE_CHOICES = [
    rc("rh-p12-rn", ("max_position_limit", "min_position_limit"), 0, 1150, "PAGE",
       "| Max Position(Close) | Min Position(Open) |",
       note="the gripper's stroke, 0 (open) ~ 1,150 (closed), from the Max/Min Position Limit description table "
            "('Max Position(Close) 1,150', 'Min Position(Open) 0'); the legacy PRO donor page's full width does not "
            "apply to a gripper"),
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
    rc("mx1", "present_speed", 0, 2047, "PAGE",
       ("0 ~ 2,047 (0x000 ~ 0x7FF) can be used", "0~2047 (0x000 ~ 0x7FF) can be used")),
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
