"""Reading DynamixelSDK's control tables (../shared/reference/sdk-control-tables/): the registry
`dynamixel.model` (model number -> file) and one `<model>.model` file's `[control table]`
section. Every line is read or refused with its file and line number: a table that parses wrong
would make the cross-check compare nothing."""
import re
from dataclasses import dataclass

REGISTRY = "dynamixel.model"

# `xl330_m288_fw52.model`: the table of firmware 52 and older (the suffix is the last version).
FIRMWARE_SUFFIX = re.compile(r"^(?P<base>.+)_fw(?P<last>\d+)\.model$")


@dataclass(frozen=True)
class SdkItem:
    """One row of a `[control table]` section, as the SDK prints it."""

    address: int
    size: int
    name: str
    line: int


@dataclass(frozen=True)
class SdkFile:
    """One `.model` file: its name, the firmware it is limited to, and its rows in file order."""

    file: str
    items: tuple
    base_file: str  # the file of the model (itself, or `x.model` for `x_fw52.model`)
    last_firmware: int | None  # `_fwNN`: firmware NN and older; None: no limit in the name


def firmware_limit(file: str) -> tuple[str, int | None]:
    """('xl330_m288.model', 52) for 'xl330_m288_fw52.model'; (file, None) without the suffix."""
    m = FIRMWARE_SUFFIX.match(file)
    if not m:
        return file, None
    return m.group("base") + ".model", int(m.group("last"))


def parse_registry(text: str, origin: str = REGISTRY) -> dict[str, int]:
    """`dynamixel.model`: 'Number<TAB>Name' then one 'number<TAB>file' a line, as file -> number.
    A file or a number listed twice is refused (the SDK's lookup would depend on order)."""
    lines = text.splitlines()
    if not lines or lines[0].split("\t") != ["Number", "Name"]:
        raise ValueError(f"{origin}:1: expected the header 'Number<TAB>Name'")
    by_file: dict[str, int] = {}
    by_number: dict[int, str] = {}
    for number, line in enumerate(lines[1:], 2):
        if not line.strip():
            continue
        cells = line.split("\t")
        if len(cells) != 2 or not cells[0].isdigit() or not cells[1].endswith(".model"):
            raise ValueError(f"{origin}:{number}: expected '<model number><TAB><file>.model', got {line!r}")
        value, file = int(cells[0]), cells[1]
        if file in by_file:
            raise ValueError(f"{origin}:{number}: {file} is listed twice")
        if value in by_number:
            raise ValueError(f"{origin}:{number}: {value} is listed twice ({by_number[value]}, {file})")
        by_file[file], by_number[value] = value, file
    return by_file


def parse_model_file(text: str, file: str) -> SdkFile:
    """The `[control table]` section of `file` ('Address<TAB>Size<TAB>Data Name' rows up to the
    next section); the `[type info]` and `[unit info]` sections are not read."""
    rows: list[SdkItem] = []
    section = None
    header_seen = False
    for number, raw in enumerate(text.splitlines(), 1):
        line = raw.rstrip("\r")
        if line.startswith("["):
            if not line.endswith("]"):
                raise ValueError(f"{file}:{number}: unterminated section header {line!r}")
            if line == "[control table]" and header_seen:
                raise ValueError(f"{file}:{number}: a second [control table] section")
            section = line
            continue
        if section != "[control table]" or not line.strip():
            continue
        cells = line.split("\t")
        if not header_seen:
            if cells != ["Address", "Size", "Data Name"]:
                raise ValueError(f"{file}:{number}: expected the header 'Address<TAB>Size<TAB>Data Name'")
            header_seen = True
            continue
        if len(cells) != 3 or not cells[0].isdigit() or not cells[1].isdigit() or not cells[2].strip():
            raise ValueError(f"{file}:{number}: expected '<address><TAB><size><TAB><name>', got {line!r}")
        if cells[2] != cells[2].strip():
            raise ValueError(f"{file}:{number}: name with surrounding blanks {cells[2]!r}")
        if any(r.name == cells[2] for r in rows):
            raise ValueError(f"{file}:{number}: {cells[2]!r} is listed twice")
        rows.append(SdkItem(int(cells[0]), int(cells[1]), cells[2], number))
    if not header_seen:
        raise ValueError(f"{file}: no [control table] section")
    if not rows:
        raise ValueError(f"{file}: the [control table] section has no rows")
    base, last = firmware_limit(file)
    return SdkFile(file, tuple(rows), base, last)
