"""Which item of a model view an SDK `Data Name` stands for. The rules are tried in order and
the first that finds anything decides; finding two items is an error, finding none is a
difference (the model lacks the item), so no SDK name is ever passed over.

1. the same name;
2. the same name but for case, blanks and punctuation ('BUS Watchdog' = 'Bus Watchdog');
3. the same without parenthesised parts, with the pages' misspellings corrected, compared with
   names and keys ('Secondary ID' = 'Secondary(Shadow) ID' = 'Sencondary ID', key
   `secondary_id`);
4. an alias: a different name the e-Manual page prints for the SDK's item (ALIASES);
5. the indirect aliases `Indirect Address Write/Read` and `Indirect Data Write/Read`, which name
   no item of the pages: the SDK's start of the block EasySDK writes (Write) or reads (Read)
   through, so they stand for the model's Indirect Address n (Data n) at the SDK's address; the
   comparison then checks that Address and Data name the same n (sdk_compare.py).

Found by reading all 60 SDK files against their e-Manual pages (every other name is rule 1, 2
or 3)."""
import re
from dataclasses import dataclass

from model_views import INDIRECT_NAME, ModelItem, ModelView

# Rule 3: words the e-Manual pages misspell, and their spelling.
MISSPELLINGS = {
    "sencondary": "secondary",  # 'Sencondary ID' / 'Sencondary(Shadow) ID': P, PRO(A) pages
}

# Rule 4: SDK name -> the names the pages print for it.
ALIASES = {
    # mx_64.model, mx_106.model: address 13; the MX-64(2.0) and MX-106(2.0) pages print
    # 'Protocol Version' there (MX-28(2.0): 'Protocol Type').
    "Protocol Type": ("Protocol Version",),
}

# Rule 5: SDK alias -> the kind of indirect item it stands for.
INDIRECT_ALIASES = {
    "Indirect Address Write": "Address",
    "Indirect Address Read": "Address",
    "Indirect Data Write": "Data",
    "Indirect Data Read": "Data",
}

RULES = ("name", "case", "spelling", "alias", "indirect alias")


@dataclass(frozen=True)
class NameMatch:
    """The items an SDK name was found to stand for, and the rule that found them."""

    items: tuple
    rule: str | None  # one of RULES; None when nothing was found

    @property
    def item(self) -> ModelItem | None:
        return self.items[0] if len(self.items) == 1 else None


def folded(name: str) -> str:
    """Rule 2's form: lower case, letters and digits only ('BUS Watchdog' -> 'buswatchdog')."""
    return re.sub(r"[^0-9a-z]+", "", name.casefold())


def spelled(name: str) -> str:
    """Rule 3's form: without parenthesised parts, words spelled right, joined by '_' like the
    model keys ('Sencondary(Shadow) ID' -> 'secondary_id'; key 'secondary_id' stays)."""
    words = re.findall(r"[0-9a-z]+", re.sub(r"\([^)]*\)", " ", name.casefold()))
    return "_".join(MISSPELLINGS.get(w, w) for w in words)


def indirect_slot(item: ModelItem) -> tuple[str, int] | None:
    """('Address', 7) for 'Indirect Address 7'; None for any other item."""
    m = INDIRECT_NAME.match(item.name)
    return (m.group(1), int(m.group(2))) if m else None


def find(sdk_name: str, sdk_address: int, view: ModelView) -> NameMatch:
    """The items of `view` that `sdk_name` (at `sdk_address` in the SDK file) stands for."""
    items = view.items
    tries = (
        ("name", lambda i: i.name == sdk_name),
        ("case", lambda i: folded(i.name) == folded(sdk_name)),
        ("spelling", lambda i: spelled(sdk_name) in (spelled(i.name), spelled(i.key))),
        ("alias", lambda i: i.name in ALIASES.get(sdk_name, ())),
    )
    for rule, matches in tries:
        found = tuple(i for i in items if matches(i))
        if found:
            return NameMatch(found, rule)
    kind = INDIRECT_ALIASES.get(sdk_name)
    if kind:
        found = tuple(i for i in items
                      if i.address == sdk_address and (indirect_slot(i) or ("", 0))[0] == kind)
        if found:
            return NameMatch(found, "indirect alias")
    return NameMatch((), None)
