"""Read-only access to ../shared/reference: the control-table pages, their include blocks (with
the Liquid branch of a product group selected) and models.tsv."""

from __future__ import annotations

from pathlib import Path

from .markdown import select_liquid_branch

# Tags whose include file has a different name (includes/README.md).
TAG_ALIASES = {"control_table_mx_baudrate": "control_table_baudrate"}


class Reference:
    """Read-only view of ../shared/reference."""

    def __init__(self, root: Path):
        self.root = root
        self.pages_dir = root / "control-tables"
        self.includes_dir = self.pages_dir / "includes"
        if not self.pages_dir.is_dir():
            raise SystemExit(f"convert_models: no control-tables/ under {root}")
        self.tsv = self._read_tsv(root / "models.tsv")
        self._cache: dict[str, str] = {}

    @staticmethod
    def _read_tsv(path: Path) -> dict[str, dict]:
        lines = path.read_text(encoding="utf-8").splitlines()
        cols = lines[0].split("\t")
        rows = {}
        for line in lines[1:]:
            if line.strip():
                row = dict(zip(cols, line.split("\t")))
                rows[row["control_table_file"].removesuffix(".md")] = row
        return rows

    def page_names(self) -> list[str]:
        """Names of every control-table page (file stems), sorted."""
        return sorted(p.stem for p in self.pages_dir.glob("*.md"))

    def text(self, rel: str) -> str:
        """A file of the reference by relative path, read once."""
        if rel not in self._cache:
            self._cache[rel] = (self.root / rel).read_text(encoding="utf-8")
        return self._cache[rel]

    def include(self, name: str, group: str) -> str | None:
        """An include by snake name, Liquid branch for `group` selected; None when not copied."""
        name = TAG_ALIASES.get(name, name)
        path = self.includes_dir / f"{name}.md"
        if not path.exists():
            return None
        return select_liquid_branch(path.read_text(encoding="utf-8"), group)
