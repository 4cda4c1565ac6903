"""What a page says about firmware versions: the versions its items need ("available from
Firmware v41", with the includes of its description sections expanded for its product group) and
the older firmware whose table differs ("Firmware versions prior to V53 support up to 20 Indirect
Address/Data items..."). The builder checks the model's firmware_version against the first and
writes the second as the model's firmware_variants.
"""

from __future__ import annotations

import re
from dataclasses import dataclass

from .markdown import select_liquid_branch
from .page import Page
from .reference import Reference

# A sentence that makes a feature need a firmware: "available from (the) firmware V45",
# "Firmware v41 or above", "firmware version V11 or higher". Emphasis is stripped first.
_NEEDS = re.compile(r"available from (?:the )?firmware (?:version )?v(\d+)"
                    r"|firmware (?:version )?v(\d+) or (?:above|higher)", re.I)
# {% assign name = "value" %} and {{ name }}: the includes name the version per product group.
_ASSIGN = re.compile(r"{%\s*assign\s+(\w+)\s*=\s*\"([^\"]*)\"\s*%}")
# The X330 pages' note on the Indirect blocks of older firmware.
_OLDER_INDIRECT = re.compile(
    r"Firmware versions prior to V(\d+) support up to (\d+) Indirect Address/Data items\. The address "
    r"range for Indirect Address is (\d+) ~ (\d+), and for Indirect Data is (\d+) ~ (\d+)\.")


@dataclass(frozen=True)
class Need:
    """A firmware version that a description section of the page requires of its item."""
    version: int
    section: str       # the section's heading, e.g. "Realtime-Tick (50)"
    addresses: tuple   # the addresses the heading names
    quote: str         # the sentence, as printed


def _resolve_assigns(text: str) -> str:
    values = dict(_ASSIGN.findall(text))
    text = _ASSIGN.sub("", text)
    return re.sub(r"{{\s*(\w+)\s*}}", lambda m: values.get(m.group(1), m.group(0)), text)


def _line(text: str, at: int) -> str:
    """The line of `text` holding position `at`, whitespace normalised: the quote of a need."""
    start = text.rfind("\n", 0, at) + 1
    end = text.find("\n", at)
    return " ".join(text[start:end if end >= 0 else None].split())


def _for_group(text: str, group: str) -> str:
    """`text` with every level of its product-group Liquid blocks resolved (select_liquid_branch
    resolves one level; the Shutdown include nests its 'Firmware v41 or above' one deeper)."""
    while True:
        resolved = select_liquid_branch(text, group)
        if resolved == text:
            return _resolve_assigns(text)
        text = resolved


def firmware_needs(ref: Reference, page: Page) -> list[Need]:
    """Every 'available from firmware vNN' of the page's description sections, includes expanded
    with the Liquid branch of the page's product group. Table rows are skipped: they name other
    products' firmware (Protocol Type's 'MX-28/64/106 with Firmware v39 or above')."""
    needs = []
    for sec in page.sections:
        text = _for_group(page.section_text(sec, ref), page.group).replace("**", "")
        text = "\n".join(line for line in text.splitlines() if not line.lstrip().startswith("|"))
        for m in _NEEDS.finditer(text):
            version = int(m.group(1) or m.group(2))
            needs.append(Need(version, sec.title, tuple(sec.addresses), _line(text, m.start())))
    return needs


@dataclass(frozen=True)
class OlderIndirect:
    """The page's note on an older firmware's Indirect blocks."""
    before: int        # "prior to V53": the firmware that brought the current layout
    count: int
    address: int
    data: int
    quote: str


def older_indirect(page: Page) -> OlderIndirect | None:
    """The 'Firmware versions prior to VNN ...' note of the page, checked for consistency; None when
    the page has none."""
    m = _OLDER_INDIRECT.search(page.text.replace("**", ""))
    if not m:
        return None
    before, count, a0, a1, d0, d1 = (int(g) for g in m.groups())
    if a1 != a0 + 2 * count - 1 or d1 != d0 + count - 1:
        raise ValueError(f"{page.name}: the older-firmware Indirect note's ranges do not hold {count} items")
    return OlderIndirect(before, count, a0, d0, m.group(0))
