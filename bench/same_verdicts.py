"""Whether two versions of the analyzer judge stores alike: each store is copied twice, analysed by
`python -m harness analyze` of the revision given (extracted with `git archive`) and of this
checkout, and every row of the tables below compared, both ways, duplicates counted. Not a
benchmark (`make bench` does not run it); the proof that a speed change kept every verdict:

    .venv/bin/python bench/same_verdicts.py --before main reports/campaign.duckdb reports/targeted.duckdb
"""
from __future__ import annotations

import argparse
import os
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

import duckdb

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from harness.store.sql import render_bench  # noqa: E402

# The verdict tables, and the views of Tables II-IV and of the flag's accuracy read from them.
COMPARED = ("verdicts", "verdicts_internal", "trace_robustness", "tp_rates", "fp_rates", "table_values", "inversions")


def checkout(revision: str, into: Path) -> Path:
    """The files of `revision` under `into`, importable as `harness` from there (the wheel maps
    sql/ and missions/ into the package; the links do the same for a plain folder)."""
    into.mkdir()
    archive = subprocess.run(["git", "archive", revision], cwd=ROOT, check=True, capture_output=True).stdout
    subprocess.run(["tar", "-x", "-C", str(into)], input=archive, check=True)
    for folder in ("sql", "missions"):
        (into / "harness" / folder).symlink_to(into / folder)
    return into


def analyse(code: Path, store: Path, properties: Path | None) -> None:
    """`analyze` of the store by the code under `code` (the installed bench may be another
    checkout's: a git worktree shares its main checkout's environment)."""
    env = dict(os.environ, PYTHONPATH=str(code))
    given = ["--properties", str(properties.resolve())] if properties else []
    done = subprocess.run([sys.executable, "-m", "harness", "analyze", "--db", str(store), *given],
                          cwd=store.parent, env=env, capture_output=True, text=True)
    if done.returncode:
        raise SystemExit(f"analyze of {store} with {code} failed:\n{done.stderr}")


def differences(before: Path, after: Path) -> list[str]:
    """Per compared table: its row count, and the rows found on one side only (none: identical)."""
    con = duckdb.connect()
    con.execute(f"attach '{before}' as b (read_only); attach '{after}' as a (read_only)")
    found = []
    for table in COMPARED:
        only_before, only_after, rows = con.execute(render_bench("same_rows", table=table)).fetchone()
        found.append(f"{table}: {rows:,} rows, {only_before} only before, {only_after} only after")
        if only_before or only_after:
            found[-1] += "  <-- DIFFERENT"
    return found


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--before", default="main", help="the revision to compare with (default: %(default)s)")
    p.add_argument("--properties", type=Path, help="for stores that record no target folder (synthetic ones)")
    p.add_argument("stores", nargs="+", type=Path)
    args = p.parse_args()
    different = False
    with tempfile.TemporaryDirectory() as tmp:
        old = checkout(args.before, Path(tmp) / "before")
        for store in args.stores:
            copies = [Path(tmp) / f"{side}-{store.name}" for side in ("before", "after")]
            for code, copy in zip((old, ROOT), copies):
                shutil.copy(store, copy)
                analyse(code, copy, args.properties)
            found = differences(*copies)
            different |= any("DIFFERENT" in line for line in found)
            print(f"{store} ({args.before} / this checkout):\n  " + "\n  ".join(found), flush=True)
    print("DIFFERENT verdicts" if different else "every row identical")
    return 1 if different else 0


if __name__ == "__main__":
    raise SystemExit(main())
