"""The sections of the report's index, as data (sections.toml): which ones a store gets, in which
order, and which tables each shows and writes as CSV. Nothing else lists them: the index's links
and body and the CSV files are made from these entries."""
from __future__ import annotations

import tomllib
from dataclasses import dataclass
from pathlib import Path

from harness.errors import UntimelyError

REGISTRY = Path(__file__).parent / "sections.toml"


@dataclass(frozen=True)
class Section:
    id: str  # the HTML id its link points to; its body is templates/sections/<id>.html.j2 if there is one
    nav: str  # its name in the index's links
    reads: tuple[str, ...]  # the store relations it needs: without one of them it is left out
    heading: str = ""  # its title (default: nav)
    note: str = ""  # what a section without a template of its own says above its tables
    tables: tuple[str, ...] = ()  # the tables it shows
    csv: tuple[str, ...] = ()  # the tables written as CSV files beside the index

    @property
    def title(self) -> str:
        return self.heading or self.nav


def registry() -> list[Section]:
    """Every section, in reading order (the order of the file's entries)."""
    entries = tomllib.loads(REGISTRY.read_text(encoding="utf-8"))["section"]
    keys = set(Section.__dataclass_fields__)
    for e in entries:  # a typo in a key would otherwise surface as a TypeError without the file
        if set(e) - keys or not {"id", "nav", "reads"} <= set(e):
            raise UntimelyError(f"{REGISTRY}: section {e.get('id')!r} has keys {sorted(e)}; give id, nav and "
                                f"reads, and only keys among {sorted(keys)}")
    return [Section(**{k: tuple(v) if isinstance(v, list) else v for k, v in e.items()}) for e in entries]


def shown(relations: set[str]) -> list[Section]:
    """The sections whose relations the store holds, in reading order."""
    return [s for s in registry() if set(s.reads) <= relations]
