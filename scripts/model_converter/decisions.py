"""Model-level decisions, as data: what the pages do not state (firmware version, reply timing,
boot time), baud tables that were not copied, and the Indirect blocks the pages must show. Each
entry carries the note written into the model with it.
"""

from __future__ import annotations

EMANUAL_INCLUDES = "https://github.com/ROBOTIS-GIT/emanual/blob/master/_includes/en/dxl/"

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
