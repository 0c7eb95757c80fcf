"""Beside reelay (past-time MTL runtime monitors, https://github.com/doganulus/reelay, from PyPI):
per-property throughput on the same events, one core each, in events per CPU second (which a
busy machine disturbs less than the wall clock).

The events of a synthetic store (analyzer_bench.py's, 1 million by default) are judged by the
analyzer with DuckDB on one thread, all 25 Dala properties (events x properties / s) and
PRE(ndd.GotoPosition) alone; reelay monitors the same events, in trace order, for that
property written in its past-time MTL: at a GotoPosition request, SetParams has replied ok
since the trace began, `{goto} -> ((not {start}) since {setparams_ok})`. reelay's events are
built before its clock starts; the analyzer's clock counts all it does (rendering, grouping the
events into requests, every verdict with its alternatives, writing them, the views). Each
figure is the median of `--repeat` measurements (3). Target: the analyzer at least 20x reelay
per property. Not a test:

    .venv/bin/python bench/reelay_bench.py [--events 1000000] [--repeat 3]
"""
from __future__ import annotations

import argparse
import statistics
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from analyzer_bench import judge, synthesise, traces_for  # noqa: E402
from harness import DEFAULT_MISSION_DIR  # noqa: E402
from harness.store.database import connect  # noqa: E402
from harness.store.sql import render_bench  # noqa: E402
from harness.target.interface import load_interface, load_properties  # noqa: E402

PROPERTY = "PRE(ndd.GotoPosition)"
FORMULA = "{goto} -> ((not {start}) since {setparams_ok})"
TARGET = 20


def reelay_events_s(path: Path) -> tuple[float, int]:
    """reelay's events per CPU second monitoring FORMULA over the store's events, and how many
    times its verdict turned false."""
    import reelay
    con = connect(path)
    rows = con.execute(render_bench("reelay_events")).fetchall()
    con.close()
    stream = [{"start": start, "goto": goto, "setparams_ok": ok} for start, goto, ok in rows]
    monitor = reelay.discrete_timed_monitor(pattern=FORMULA)
    false, started = 0, time.process_time()
    for event in stream:
        if monitor.update(event).get("value") is False:
            false += 1
    return len(stream) / (time.process_time() - started), false


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--events", type=int, default=1_000_000)
    p.add_argument("--seed", type=int, default=2012)
    p.add_argument("--repeat", type=int, default=3, help="measurements of each, whose median is reported")
    args = p.parse_args()
    interface = load_interface(DEFAULT_MISSION_DIR / "interface.toml")
    properties = load_properties(DEFAULT_MISSION_DIR / "properties.toml", interface)
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "reelay.duckdb"
        con = connect(path)
        synthesise(con, interface, traces_for(args.events, 100), 100, args.seed)
        con.close()
        repeat = range(max(args.repeat, 1))
        every = [judge(path, properties, threads=1) for _ in repeat]
        alone = [judge(path, [p for p in properties if p.id == PROPERTY], threads=1) for _ in repeat]
        reelays = [reelay_events_s(path) for _ in repeat]
    events = every[0].events
    ours_every = statistics.median(j.events * j.properties / j.cpu_s for j in every)
    ours_alone = statistics.median(j.events / j.cpu_s for j in alone)
    theirs, false = statistics.median(r for r, _ in reelays), reelays[0][1]
    print(f"the same {events:,} events, one core each (DuckDB on one thread; reelay's monitor in this process), "
          f"per CPU second, medians of {len(every)}")
    print(f"reelay: {PROPERTY} as {FORMULA!r}: {theirs:,.0f} events per CPU second "
          f"({false:,} changes of the verdict to false)")
    for what, ours in ((f"all {every[0].properties} properties", ours_every), (f"{PROPERTY} alone", ours_alone)):
        print(f"analyzer, DuckDB on one thread, {what}: {ours:,.0f} property-events per CPU second = "
              f"{ours / theirs:.1f}x reelay "
              f"(target >= {TARGET}x: {'met' if ours / theirs >= TARGET else 'NOT met'})")
    print(f"README: per-property throughput beside reelay, one core (`bench/reelay_bench.py`) | "
          f"{ours_every / theirs:.1f}x ({ours_every / 1e6:.2f} M property-events per CPU s over all "
          f"{every[0].properties} properties; {PROPERTY} alone {ours_alone / theirs:.1f}x; reelay {theirs / 1e6:.2f} M "
          "events per CPU s through its Python binding) | ≥ 20x")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
