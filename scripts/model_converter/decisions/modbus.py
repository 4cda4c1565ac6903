"""Modbus RTU decisions, as data: the lowest firmware that speaks it, and the rows whose printed
Modbus address a page gets wrong, each with its evidence. Which models list "modbus" at all is
model_fields.PROTOCOLS; the register map itself is a rule (modbus_map.py, docs/modbus.md), read
from and checked against the pages' Modbus Address column.
"""

from __future__ import annotations

from . import EMANUAL_INCLUDES

# The reference's Modbus notes (../shared/reference/modbus/modbus-rtu.md "Where DYNAMIXEL speaks it").
MODBUS_REFERENCE = "modbus/modbus-rtu.md 'Where DYNAMIXEL speaks it'"

# The lowest firmware that speaks Modbus RTU, per variant: the builder refuses a model listing
# "modbus" whose firmware_version (or a firmware variant's) is below it.
MODBUS_FIRMWARE = {
    "p": (11, "the Protocol Type(13) block includes/docs-partials/pro__p_control_table_13_protocol_type.mdx: "
              "'In order to use Modbus-RTU you must update to firmware version V11 or higher'"),
    # The page imports that same Docusaurus block (V11); the e-Manual include it was migrated from
    # asks V12 in its rh_p12_rna branch: the higher one is kept.
    "rh-p12-rna": (12, f"the rh_p12_rna branch of the e-Manual's Protocol Type(13) include "
                       f"{EMANUAL_INCLUDES}p/control_table_13_protocol_type.md, as {MODBUS_REFERENCE} cites it "
                       "(the Docusaurus block the page imports says V11, for every product: the higher is kept)"),
}

# Rows whose printed Modbus address breaks the rule every other row of every P page follows
# (40001 + floor(address / 2), Lo Byte at an even address, Hi Byte at an odd one): per page, the
# address -> (the cell as printed, why the rule is kept). The converter refuses any other
# disagreement, and an entry that no longer matches the page (the page was fixed or changed).
MODBUS_ERRATA = {
    "ph54-100-s500-r": {
        13: ("40007 (Lo Byte)", "Protocol Type(13) is at an odd address, the high byte of 40007, as the five other "
                                "P pages print it ('40007 (Hi Byte)'); the low byte of 40007 is address 12, "
                                "Secondary ID"),
    },
    "rh-p12-rna": {
        # The page lists Position P Gain(532) before Position I Gain(530) and numbers the column in
        # row order; the P pages list 530 first, as 40266, and 532 as 40267.
        530: ("40267", "the page lists Position P Gain(532) before Position I Gain(530) and numbers its Modbus "
                       "column in row order; the P pages, in address order, print 530 as 40266 and 532 as 40267"),
        532: ("40266", "the page lists Position P Gain(532) before Position I Gain(530) and numbers its Modbus "
                       "column in row order; the P pages, in address order, print 530 as 40266 and 532 as 40267"),
    },
}
