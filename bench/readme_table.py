"""Rewrite the README's performance table rows from `make bench`'s output, so that no figure of
theirs is typed: every line `README: what | measured | target` that a bench printed (kept by
bench/run.py in reports/bench/*.txt) replaces the table's row whose first cell is `what`, or is
added at the table's end. Run after `make bench` (or `python bench/run.py NAMES`):

    .venv/bin/python bench/readme_table.py
"""
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
README = ROOT / "README.md"
KEPT = ROOT / "reports" / "bench"
HEADING = "## Measured (`make bench`"


def measured() -> dict[str, str]:
    """What each bench said, by row: the row's markdown."""
    rows = {}
    for kept in sorted(KEPT.glob("*.txt")):
        for line in kept.read_text().splitlines():
            if line.startswith("README: "):
                cells = [c.strip() for c in line.removeprefix("README: ").split(" | ")]
                rows[cells[0]] = "| " + " | ".join(cells) + " |"
    return rows


def rewrite(text: str, rows: dict[str, str]) -> str:
    lines = text.splitlines()
    start = next(i for i, line in enumerate(lines) if line.startswith(HEADING))
    first = next(i for i in range(start, len(lines)) if lines[i].startswith("|"))
    end = next((i for i in range(first, len(lines)) if not lines[i].startswith("|")), len(lines))
    left = dict(rows)
    for i in range(first + 2, end):  # past the header and its rule
        what = lines[i].split("|")[1].strip()
        if what in left:
            lines[i] = left.pop(what)
    lines[end:end] = left.values()
    return "\n".join(lines) + "\n"


def main() -> int:
    rows = measured()
    if not rows:
        print(f"no bench output in {KEPT}: run `make bench` first", file=sys.stderr)
        return 1
    README.write_text(rewrite(README.read_text(), rows))
    print(f"{len(rows)} rows of {README.name} written from {KEPT}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
