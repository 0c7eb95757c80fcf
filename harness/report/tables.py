"""A table as the report shows it and writes it to CSV: one shape for both, so they cannot drift."""
from __future__ import annotations

import csv
from dataclasses import dataclass, field
from pathlib import Path

from harness.textable import percent


@dataclass
class Table:
    name: str  # CSV file stem and HTML id
    columns: list[str]
    rows: list[tuple]
    links: dict[tuple[int, int], str] = field(default_factory=dict)  # (row, column) -> href
    percent: frozenset[str] = frozenset()  # columns holding rates in [0, 1], shown as %
    note: str = ""

    def column(self, name: str) -> list:
        i = self.columns.index(name)
        return [row[i] for row in self.rows]

    def records(self) -> list[dict]:
        return [dict(zip(self.columns, row)) for row in self.rows]

    def link_column(self, name: str, href) -> "Table":
        """Link each cell of a column to href(value), when href gives one."""
        i = self.columns.index(name)
        for r, row in enumerate(self.rows):
            if (target := href(row[i])) is not None:
                self.links[(r, i)] = target
        return self

    def cells(self):
        """Rows of (text, href, raw value) for the HTML template."""
        for r, row in enumerate(self.rows):
            yield [(_text(v, c in self.percent), self.links.get((r, i)), v)
                   for i, (c, v) in enumerate(zip(self.columns, row))]

    def write_csv(self, folder: Path) -> Path:
        path = folder / f"{self.name}.csv"
        with open(path, "w", newline="", encoding="utf-8") as f:
            writer = csv.writer(f)
            writer.writerow(self.columns)
            writer.writerows(["" if v is None else v for v in row] for row in self.rows)
        return path


def query_table(con, name: str, sql: str, params=(), **options) -> Table:
    cursor = con.execute(sql, list(params))
    return Table(name, [d[0] for d in cursor.description], cursor.fetchall(), **options)


def yes_no(value: bool | None) -> str:
    """A boolean as the report shows it; NULL (undecidable) stays empty."""
    return "" if value is None else "yes" if value else "no"


def _text(value, is_rate: bool) -> str:
    if is_rate:
        return percent(value)
    if value is None:
        return ""
    if isinstance(value, bool):
        return yes_no(value)
    if isinstance(value, float):
        return f"{value:.4g}"
    return str(value)
