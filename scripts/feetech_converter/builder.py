"""One FEETECH model file: the model-level fields (decisions.py), its items (items.py), and the
notes saying where lerobot's control table differs from the model."""

from __future__ import annotations

from .decisions import (BAUD_NOTE, BOOT_NOTE, FAMILIES, FEETECH_BAUDS, KG_CM_NM, PROTOCOL_NOTE,
                        RETURN_DELAY_NOTE, TIMING, TIMING_NOTE, Model)
from .items import build_items
from .reference import FeetechReference

WIKI_PAGES = {"sts": "memory-sts.md", "sms": "memory-sms.md", "scs": "memory-scscl.md", "hls": "memory-hls.md"}
WIKI_COMMIT = "9522ce192f4c7bfd40b0c3f72c0b3bb52cc24630"
LOCK_NOTE = ("items.lock_flag: FEETECH's Lock flag (0: EEPROM writes persist after power-off; 1: they do not), "
             "not DYNAMIXEL's Lock: as documented it never refuses a write")


def lerobot_notes(ref: FeetechReference, items: list[dict]) -> list[str]:
    """Every lerobot entry whose address and size are not an item's of the model."""
    by_address = {i["address"]: i for i in items}
    notes = []
    for entry in ref.lerobot:
        item = by_address.get(entry.address)
        if item is not None and item["size"] == entry.size:
            continue
        if item is None:
            inside = next((i for i in items if i["address"] < entry.address < i["address"] + i["size"]), None)
            what = (f"inside {inside['key']} ({inside['address']}, {inside['size']})" if inside
                    else "an address FEETECH's table leaves undefined")
        else:
            what = f"{item['key']} there is {item['size']} byte{'s' if item['size'] > 1 else ''}"
        notes.append(f"lerobot: {entry.name} ({entry.address}, {entry.size}): {what}; the model follows "
                     "FEETECH's table")
    return notes


def build_model(ref: FeetechReference, model: Model) -> dict:
    """The model file's content, in the field order of docs/model-format.md."""
    family = FAMILIES[model.family]
    items = build_items(ref, model, family)
    motion: dict = {"degrees_per_pulse": model.degrees_per_pulse, "velocity_unit_rpm": round(model.velocity_unit_rpm, 10)}
    if model.current_unit_ma is not None:
        motion["current_unit_ma"] = model.current_unit_ma
    motion["stall_torque_nm"] = round(model.stall_torque_kgcm * KG_CM_NM, 4)
    motion["nominal_voltage_v"] = model.nominal_voltage_v
    notes = [model.model_number_note, model.firmware[2], PROTOCOL_NOTE,
             f"byte_order: {family.byte_order}, the END item (2) of FEETECH's table "
             f"({'1: big-endian' if family.byte_order == 'big' else '0: little-endian'})",
             f"family: {family.name}, FEETECH's series (its row of the family traits table: docs/feetech.md)",
             BAUD_NOTE, "default_id: 1, default_baud_index: 0, the table's initial values",
             RETURN_DELAY_NOTE, TIMING_NOTE, BOOT_NOTE, *model.motion_notes,
             f"motion.current_unit_ma: {model.current_unit_ma}, the unit of Present current" if model.current_unit_ma
             else "motion.current_unit_ma: absent, the table has no current item",
             f"motion.{_SPEC_FIELDS}: {motion['stall_torque_nm']} N·m at {model.nominal_voltage_v} V, "
             f"{model.spec_note}", LOCK_NOTE if any(i["key"] == "lock_flag" for i in items) else None,
             *family.notes, *model.notes, *lerobot_notes(ref, items)]
    page = WIKI_PAGES[model.family]
    return {
        "name": model.name,
        "title": model.title,
        "model_number": model.model_number,
        "firmware_version": model.firmware[0],
        "family": model.family,
        "protocols": ["feetech"],
        "default_id": 1,
        "baud_rates": [{"index": i, "bps": bps} for i, bps in enumerate(FEETECH_BAUDS)],
        "default_baud_index": 0,
        "return_delay_unit_us": 2,
        "byte_order": family.byte_order,
        "timing": dict(TIMING),
        "motion": motion,
        "source": f"feetech/{model.reference} (ftservo/ftservo-wiki docs/en/reference/parameter/{page} @ {WIKI_COMMIT})",
        "notes": [n for n in notes if n],
        "items": items,
    }


_SPEC_FIELDS = "stall_torque_nm / nominal_voltage_v"
