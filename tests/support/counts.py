"""The suite's counts that README.md and docs/contributing.md state, generated rather than typed:
`make counts` (python -m tests.support.counts) collects the suite, whole and fast (`-m "not slow"`),
and writes both numbers into the two files; tests/project/test_suite_layout.py checks them."""
from __future__ import annotations

import re
import subprocess
import sys

from tests.support.paths import ROOT, TESTS

# How both files state the counts: "1,042 of the suite's 1,259 tests" (\s+ where a line may break).
COUNTS = re.compile(r"(?P<fast>[\d,]+)(?P<a>\s+)of(?P<b>\s+)the(?P<c>\s+)suite's(?P<d>\s+)(?P<all>[\d,]+)(?P<e>\s+)tests")
STATED = (ROOT / "README.md", ROOT / "docs" / "contributing.md")


def collected(*marker: str) -> int:
    """How many tests pytest collects from tests/ (with `-m MARKER` when given)."""
    found = subprocess.run([sys.executable, "-m", "pytest", "--collect-only", "-q", "-p", "no:cacheprovider",
                            *(("-m", *marker) if marker else ()), str(TESTS)],
                           cwd=ROOT, capture_output=True, text=True, check=True)
    return sum(1 for line in found.stdout.splitlines() if "::" in line)


def stated(text: str) -> tuple[int, int]:
    """(fast, all) as a file states them."""
    match = COUNTS.search(text)
    assert match, f"no counts where {COUNTS.pattern} expects them"
    return int(match["fast"].replace(",", "")), int(match["all"].replace(",", ""))


def written(text: str, fast: int, every: int) -> str:
    return COUNTS.sub(lambda m: f"{fast:,}{m['a']}of{m['b']}the{m['c']}suite's{m['d']}{every:,}{m['e']}tests",
                       text, count=1)


def main() -> int:
    fast, every = collected("not slow"), collected()
    for path in STATED:
        path.write_text(written(path.read_text(), fast, every))
    print(f"{fast:,} of the suite's {every:,} tests are fast; written into {', '.join(p.name for p in STATED)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
