"""Model notes that explain a difference from DynamixelSDK's tables (docs/model-format.md,
"Differences from DynamixelSDK's tables"):

    sdk-control-tables: <sdk file> <SDK item>: <why>, citing control-tables/<page>.md

The SDK file is one of sdk-control-tables/*.model; the item is the SDK's Data Name as printed
(or `Model Number`); the reason cites the e-Manual page that decides the difference, which must
exist in the reference. A note that does not follow this form, or that explains no difference,
fails the test: a stale explanation would hide the next difference on that item."""
import re
from dataclasses import dataclass
from pathlib import Path

PREFIX = "sdk-control-tables:"
NOTE = re.compile(r"^sdk-control-tables:\s+(?P<file>\S+\.model)\s+(?P<item>[^:]+?):\s+(?P<why>\S.*)$")
PAGE = re.compile(r"control-tables/(?P<page>[0-9a-z+_.-]+\.md)")


@dataclass(frozen=True)
class Explanation:
    file: str
    item: str
    why: str
    pages: tuple
    note: str


def parse_note(note: str, pages_dir: Path | None) -> Explanation:
    """The explanation a `sdk-control-tables:` note gives; ValueError naming what is wrong.
    With `pages_dir`, every cited page must be a file in it."""
    m = NOTE.match(note)
    if not m:
        raise ValueError(f"not '{PREFIX} <file>.model <item>: <why>': {note!r}")
    pages = tuple(p.group("page") for p in PAGE.finditer(m.group("why")))
    if not pages:
        raise ValueError(f"cites no e-Manual page (control-tables/<page>.md): {note!r}")
    if pages_dir is not None:
        missing = [p for p in pages if not (pages_dir / p).is_file()]
        if missing:
            raise ValueError(f"cites {', '.join('control-tables/' + p for p in missing)}, which the "
                             f"reference does not have: {note!r}")
    return Explanation(m.group("file"), m.group("item").strip(), m.group("why"), pages, note)


def explanations(notes, pages_dir: Path | None) -> tuple[list[Explanation], list[str]]:
    """The explanations among `notes` (strings) and the errors of those that are malformed."""
    out, errors = [], []
    for note in notes:
        if not note.startswith(PREFIX):
            continue
        try:
            out.append(parse_note(note, pages_dir))
        except ValueError as e:
            errors.append(str(e))
    return out, errors
