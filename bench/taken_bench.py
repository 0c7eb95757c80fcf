"""How many inversions a `taken` reply settles on the out-of-process simulator (issue 23).

One campaign runs the same seeded mutants on `sim-reference` and `sim-genom` and on the same
adapters with `--taken` (`sim-reference-taken`, `sim-genom-taken`, missions/dala/suts.toml),
which reply `taken` when the layer takes each request; the oracles then place each request at
that reply. Prints per SUT the verdicts judged on both timelines, the inversions (view
`inversions`), the flagged verdicts and the load average. Real-time runs: the figures vary from
run to run with the machine's load. Not a test:

    .venv/bin/python bench/taken_bench.py [--mutants 30] [--time-scale 10] [--jobs 4] [--db STORE]

`--db`: the campaign's store, read if it exists (then the other options are unused), else built
there (by default in a temporary folder).
"""
from __future__ import annotations

import argparse
import contextlib
import io
import os
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from harness.cli import main as cli  # noqa: E402
from harness.store.database import connect  # noqa: E402
from harness.store.sql import render_bench  # noqa: E402
from harness.textable import format_table  # noqa: E402

SUTS = "sim-reference,sim-genom,sim-reference-taken,sim-genom-taken"


def run_campaign(db: Path, args) -> None:
    started = time.perf_counter()
    with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(io.StringIO()):
        code = cli(["campaign", "--db", str(db), "--mutants", str(args.mutants), "--seed", str(args.seed),
                    "--sut", SUTS, "--jobs", str(args.jobs), "--time-scale", str(args.time_scale)])
    if code != 0:
        raise SystemExit("the campaign failed")
    print(f"campaign: {args.mutants} mutants + golden on {SUTS}, time scale {args.time_scale:g}, "
          f"{args.jobs} jobs, built in {time.perf_counter() - started:.0f} s", flush=True)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--mutants", type=int, default=30)
    parser.add_argument("--seed", type=int, default=2012)
    parser.add_argument("--time-scale", type=float, default=10.0)
    parser.add_argument("--jobs", type=int, default=4)
    parser.add_argument("--db", type=Path, help="the campaign's store: read if it exists, else built there")
    args = parser.parse_args()
    load = "load average " + ", ".join(f"{v:.1f}" for v in os.getloadavg())
    with tempfile.TemporaryDirectory() as folder:
        db = args.db or Path(folder) / "taken.duckdb"
        if not db.exists():
            print(f"before: {load}", flush=True)
            run_campaign(db, args)
        con = connect(db, read_only=True)
        cursor = con.execute(render_bench("taken_per_sut"))
        print(format_table([d[0] for d in cursor.description], cursor.fetchall()))
        con.close()
    print("after: load average " + ", ".join(f"{v:.1f}" for v in os.getloadavg()))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
