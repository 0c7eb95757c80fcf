"""`make report` at scale: a store of >= 10,000 traces should be reported in < 10 s and < 100 MB.

The store is a real campaign (--mutants mutants on genom, bip-a, bip-b, so its mix of good,
bad, hung and inverted traces is the bench's own) whose traces are copied under new ids until
there are --traces of them, then judged with the 21 Dala properties. `python -m harness
report` is then timed in a process of its own (median of --repeats runs): wall time, CPU time
(a busy machine stretches the wall time, much less the CPU time), peak memory (max RSS) and the
size of what it wrote. Prints figures; never fails on a busy machine.

    .venv/bin/python bench/report_bench.py [--traces 10000] [--mutants 100]
"""
from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from harness import DEFAULT_MISSION_DIR  # noqa: E402
from harness.analyzer import materialise  # noqa: E402
from harness.interface import load_interface, load_properties  # noqa: E402
from harness.store import connect  # noqa: E402

TIME_LINE_S, SIZE_LINE_MB = 10.0, 100.0


def build(db: Path, traces: int, mutants: int) -> tuple[int, int]:
    """A campaign of `mutants` mutants, its traces copied under new ids up to `traces`, judged."""
    subprocess.run([sys.executable, "-m", "harness", "campaign", "--mutants", str(mutants), "--seed", "2012",
                    "--db", str(db)], cwd=ROOT, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    con = connect(db)
    original, top = con.execute("select count(*), max(trace_id) from traces").fetchone()
    copies = -(-traces // original) - 1
    con.execute("create temporary table copies as select range as k from range(1, ?)", [copies + 1])
    offset = f"t.trace_id + k * {top}"
    con.execute(f"insert into traces by name select {offset} as trace_id, t.* exclude (trace_id) from traces t, copies")
    for table in ("events", "internal_events", "world_events"):
        con.execute(f"insert into {table} by name select {offset} as trace_id, t.* exclude (trace_id) "
                    f"from {table} t, copies")
    interface = load_interface(DEFAULT_MISSION_DIR / "interface.toml")
    materialise(con, load_properties(DEFAULT_MISSION_DIR / "properties.toml", interface), 0.01)
    found = con.execute("select (select count(*) from traces), (select count(*) from events)").fetchone()
    con.close()
    return found


def time_report(db: Path, out: Path) -> tuple[float, float, float]:
    """Wall seconds, CPU seconds (with its worker processes) and peak memory (MB, the largest
    process) of one `python -m harness report` process."""
    started = time.perf_counter()
    child = subprocess.Popen([sys.executable, "-m", "harness", "report", "--db", str(db), "--out", str(out)],
                             cwd=ROOT, stdout=subprocess.DEVNULL)
    _, status, usage = os.wait4(child.pid, 0)
    elapsed = time.perf_counter() - started
    if status:
        raise SystemExit(f"report failed (wait status {status})")
    return elapsed, usage.ru_utime + usage.ru_stime, usage.ru_maxrss / 1024


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--traces", type=int, default=10_000, help="traces in the store (default: %(default)s)")
    p.add_argument("--mutants", type=int, default=100, help="mutants of the campaign copied (default: %(default)s)")
    p.add_argument("--repeats", type=int, default=3, help="report runs timed (default: %(default)s)")
    args = p.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        db, out = Path(tmp) / "big.duckdb", Path(tmp) / "report"
        started = time.perf_counter()
        traces, events = build(db, args.traces, args.mutants)
        print(f"(built and judged a store of {traces:,} traces, {events:,} events, "
              f"in {time.perf_counter() - started:.1f} s)")
        runs = [time_report(db, out) for _ in range(args.repeats)]
        wall, cpu = statistics.median(r[0] for r in runs), statistics.median(r[1] for r in runs)
        memory = max(r[2] for r in runs)
        written = sorted(out.rglob("*"))
        size = sum(f.stat().st_size for f in written if f.is_file()) / 1e6
        pages = sum(1 for f in written if f.name.startswith("trace-"))
        print(f"report of {traces:,} traces: {wall:.2f} s wall (median of {args.repeats}; line {TIME_LINE_S:g} s: "
              f"{wall / TIME_LINE_S:.2f} of it), {cpu:.2f} s CPU, peak memory {memory:.0f} MB, "
              f"{size:.1f} MB written (line {SIZE_LINE_MB:g} MB: {size / SIZE_LINE_MB:.2f} of it), "
              f"{pages:,} trace pages; load average {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
