"""`make report` at scale: a store of >= 10,000 traces should be reported in < 10 s and < 100 MB.

The store is a real campaign (--mutants mutants on genom, bip-a, bip-b, so its mix of good,
bad, hung and inverted traces is the bench's own) whose traces are copied under new ids until
there are --traces of them, then judged with the 21 Dala properties. `python -m harness
report` is then timed in a process of its own (median of --repeats runs): wall time, CPU time
(a busy machine stretches the wall time, much less the CPU time), peak memory and the size of
what it wrote. Peak memory is that of the largest process (its max RSS, from the kernel) and
that of all the report's processes together (sampled every 20 ms: their PSS, which counts the
pages of the shared libraries they all map once, and their RSS summed, which counts them in each).
Prints figures; never fails on a busy machine.

    .venv/bin/python bench/report_bench.py [--traces 10000] [--mutants 100] [--db STORE]
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

import psutil

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from harness import DEFAULT_MISSION_DIR  # noqa: E402
from harness.analysis.analyzer import materialise  # noqa: E402
from harness.target.interface import load_interface, load_properties  # noqa: E402
from harness.store.database import connect  # noqa: E402
from harness.store.bench_reads import event_count, trace_span  # noqa: E402
from harness.store.reads import trace_count  # noqa: E402
from harness.store.sql import render_bench  # noqa: E402

TIME_LINE_S, SIZE_LINE_MB, MEMORY_LINE_MB = 10.0, 100.0, 100.0
MB = 1024 * 1024


def build(db: Path, traces: int, mutants: int) -> None:
    """A campaign of `mutants` mutants, its traces copied under new ids up to `traces`, judged."""
    subprocess.run([sys.executable, "-m", "harness", "campaign", "--mutants", str(mutants), "--seed", "2012",
                    "--db", str(db)], cwd=ROOT, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    con = connect(db)
    original, top = trace_span(con)
    con.execute(render_bench("copied_traces", copies=-(-traces // original) - 1, top=top))
    interface = load_interface(DEFAULT_MISSION_DIR / "interface.toml")
    materialise(con, load_properties(DEFAULT_MISSION_DIR / "properties.toml", interface), 0.01, interface)
    con.close()


def time_report(db: Path, out: Path) -> dict[str, float]:
    """Wall seconds, CPU seconds (with its worker processes) and peak memory (MB: of the largest
    process, and of all of them together, as PSS and as RSS summed) of one report."""
    started = time.perf_counter()
    child = subprocess.Popen([sys.executable, "-m", "harness", "report", "--db", str(db), "--out", str(out)],
                             cwd=ROOT, stdout=subprocess.DEVNULL)
    report, pss, rss = psutil.Process(child.pid), 0.0, 0.0
    while not (done := os.wait4(child.pid, os.WNOHANG))[0]:
        now = [_memory(p) for p in [report, *_children(report)]]
        pss, rss = max(pss, sum(m[0] for m in now)), max(rss, sum(m[1] for m in now))
        time.sleep(0.02)
    _, status, usage = done
    elapsed = time.perf_counter() - started
    if status:
        raise SystemExit(f"report failed (wait status {status})")
    return {"wall": elapsed, "cpu": usage.ru_utime + usage.ru_stime, "largest": usage.ru_maxrss / 1024,
            "pss": pss, "rss": rss}


def _children(process: psutil.Process) -> list[psutil.Process]:
    try:
        return process.children(recursive=True)
    except psutil.NoSuchProcess:  # ending
        return []


def _memory(process: psutil.Process) -> tuple[float, float]:
    """(PSS, RSS) of a process in MB; nothing for one that has just ended."""
    try:
        memory = process.memory_full_info()
    except (psutil.NoSuchProcess, psutil.AccessDenied):
        return 0.0, 0.0
    return memory.pss / MB, memory.rss / MB


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--traces", type=int, default=10_000, help="traces in the store (default: %(default)s)")
    p.add_argument("--mutants", type=int, default=100, help="mutants of the campaign copied (default: %(default)s)")
    p.add_argument("--repeats", type=int, default=3, help="report runs timed (default: %(default)s)")
    p.add_argument("--db", help="an analysed store to report instead of building one (opened read-only)")
    args = p.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        db, out = Path(args.db or Path(tmp) / "big.duckdb"), Path(tmp) / "report"
        started = time.perf_counter()
        if not args.db:
            build(db, args.traces, args.mutants)
        con = connect(db, read_only=True)
        traces, events = trace_count(con), event_count(con)
        con.close()
        print(f"(a store of {traces:,} traces, {events:,} events" +
              ("" if args.db else f", built and judged in {time.perf_counter() - started:.1f} s") + ")")
        runs = [time_report(db, out) for _ in range(args.repeats)]
        wall, cpu = statistics.median(r["wall"] for r in runs), statistics.median(r["cpu"] for r in runs)
        largest, pss, rss = (max(r[k] for r in runs) for k in ("largest", "pss", "rss"))
        written = sorted(out.rglob("*"))
        size = sum(f.stat().st_size for f in written if f.is_file()) / 1e6
        pages = sum(1 for f in written if f.name.startswith("trace-"))
        print(f"report of {traces:,} traces: {wall:.2f} s wall (median of {args.repeats}; line {TIME_LINE_S:g} s: "
              f"{wall / TIME_LINE_S:.2f} of it), {cpu:.2f} s CPU, {size:.1f} MB written (line {SIZE_LINE_MB:g} MB: "
              f"{size / SIZE_LINE_MB:.2f} of it), {pages:,} trace pages; load average {os.getloadavg()[0]:.1f} "
              f"on {os.cpu_count()} cores")
        print(f"peak memory (line {MEMORY_LINE_MB:g} MB): largest process {largest:.0f} MB max RSS "
              f"({largest / MEMORY_LINE_MB:.2f} of the line); all processes together {pss:.0f} MB PSS "
              f"({pss / MEMORY_LINE_MB:.2f}), {rss:.0f} MB RSS summed ({rss / MEMORY_LINE_MB:.2f})")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
