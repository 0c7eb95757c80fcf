"""Analyzer speed: a campaign-sized store (~900 traces) should be judged in <= 3 s, and the
events judged per second are measured on a synthetic store of >= 10 million events.

The synthetic stores are built in SQL, set-based (sql/bench/synthetic_traces.sql): every choice
(service, timing, reply) is a hash of (seed, trace, request), so the same seed gives the same
store. They are judged with the 21 Dala properties, exactly as `python -m harness analyze` does.
Each judging time is also printed as a multiple of the calibration loop (calibration.py) timed
just before and after it: unlike seconds, that ratio compares across machines and loads, so a
slowdown of the analyzer shows as a larger ratio (lower is faster). Not a test:

    .venv/bin/python bench/analyzer_bench.py [--events 10000000] [--campaign reports/campaign.duckdb]
"""
from __future__ import annotations

import argparse
import shutil
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from calibration import calibrate  # noqa: E402
from harness import DEFAULT_MISSION_DIR  # noqa: E402
from harness.analysis.analyzer import materialise  # noqa: E402
from harness.target.interface import load_interface, load_properties  # noqa: E402
from harness.store.database import add_campaign, add_reply_codes, connect, place  # noqa: E402
from harness.store.sql import render_bench  # noqa: E402

# Reply shares (percent, cumulative): mostly ok, some interruptions and rejections, some unanswered.
REPLIES = [(70, "ok"), (78, "interrupted"), (82, "interrupted_excl"), (87, "wait_init"),
           (92, "disallowed"), (95, "too_many_activities"), (98, "bad_params")]  # the rest: no final reply


def synthesise(con, interface, traces: int, requests: int, seed: int) -> int:
    """`traces` traces of `requests` requests each over the interface's services; returns the event count."""
    add_campaign(con, 1, "synthetic", seed, {"traces": traces, "requests": requests})
    add_reply_codes(con, interface)
    con.execute(render_bench("synthetic_traces", seed=seed, traces=traces, requests=requests, replies=REPLIES,
                             services=[(s.module, s.name) for s in interface.services.values()]))
    place(con, "variant_positions", "sut", [f"variant-{n % 3}" for n in range(1, 4)])  # as their first traces
    return con.execute("select count(*) from events").fetchone()[0]


def judge(path: Path, properties) -> tuple[int, int, float, float]:
    """Traces, events, seconds to judge them, and the calibration loop's seconds (the median of
    loops timed just before and just after, as the machine's load was while it judged)."""
    before = calibrate()
    con = connect(path)
    started = time.perf_counter()
    materialise(con, properties, 0.01, load_interface(DEFAULT_MISSION_DIR / "interface.toml"))
    elapsed = time.perf_counter() - started
    traces, events = con.execute("select (select count(*) from traces), (select count(*) from events)").fetchone()
    con.close()
    return traces, events, elapsed, (before + calibrate()).wall_s


def report(what: str, traces: int, events: int, elapsed: float, loop: float, limit: float | None = None) -> None:
    verdict = "" if limit is None else ("  (<= %.0f s: %s)" % (limit, "yes" if elapsed <= limit else "NO"))
    print(f"{what}: {traces:,} traces, {events:,} events judged in {elapsed:.2f} s = {events / elapsed:,.0f} "
          f"events/s = {elapsed / loop:.1f} calibration loops of {loop * 1000:.0f} ms{verdict}", flush=True)


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--events", type=int, default=10_000_000, help="size of the large store (default: %(default)s)")
    p.add_argument("--seed", type=int, default=2012)
    p.add_argument("--campaign", help="also time a copy of this real campaign store")
    args = p.parse_args()
    interface = load_interface(DEFAULT_MISSION_DIR / "interface.toml")
    properties = load_properties(DEFAULT_MISSION_DIR / "properties.toml", interface)
    with tempfile.TemporaryDirectory() as tmp:
        if args.campaign:
            copy = Path(tmp) / "campaign.duckdb"
            shutil.copy(args.campaign, copy)
            report("real campaign", *judge(copy, properties), limit=3)
        # ~900 traces shaped like the golden mission's (~30 requests, ~60 events each)
        small = Path(tmp) / "small.duckdb"
        con = connect(small)
        synthesise(con, interface, 900, 30, args.seed)
        con.close()
        report("campaign-sized store", *judge(small, properties), limit=3)
        big = Path(tmp) / "big.duckdb"
        con = connect(big)
        started = time.perf_counter()
        requests = 100
        events = synthesise(con, interface, -(-args.events // (2 * requests) * 100 // 98), requests, args.seed)
        con.close()
        print(f"(built the large store, {events:,} events, in {time.perf_counter() - started:.1f} s)")
        report("large store", *judge(big, properties))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
