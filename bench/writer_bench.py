"""The campaign's single writer: how many runs per second the store absorbs, with a null SUT (the
runs cost nothing to make: one golden trace per variant, made once, written again and again under
new trace ids). The writer commits runs in batches as a campaign does (campaign.py's Batches: 64
runs per transaction, one Arrow append per table), so this is the ceiling a campaign's runs/s
meets however many jobs make them; beside it, a default campaign's runs/s on this machine
(README) says whether the writer is the bottleneck. Not a test:

    .venv/bin/python bench/writer_bench.py [--runs 4000]
"""
from __future__ import annotations

import argparse
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from harness import DEFAULT_MISSION_DIR  # noqa: E402
from harness.campaign.runs import BATCH_RUNS  # noqa: E402
from harness.sut.executive import run_script  # noqa: E402
from harness.store.appends import transaction  # noqa: E402
from harness.store.bench_reads import event_count  # noqa: E402
from harness.store.database import add_campaign, add_reply_codes, connect, insert_traces  # noqa: E402
from harness.store.record import ImportRecord  # noqa: E402
from harness.target.interface import load_interface  # noqa: E402
from harness.target.script import load_script  # noqa: E402

VARIANTS = ("genom", "bip-a", "bip-b")
CAMPAIGN_RUNS_S = 77  # the default campaign's runs/s on 2 cores (README's performance table)


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--runs", type=int, default=4000, help="runs to write (default: %(default)s)")
    args = p.parse_args()
    interface = load_interface(DEFAULT_MISSION_DIR / "interface.toml")
    script = load_script(DEFAULT_MISSION_DIR / "golden.mission", interface)
    traces = [run_script(script, sut, 7, interface, DEFAULT_MISSION_DIR / "world.toml") for sut in VARIANTS]
    with tempfile.TemporaryDirectory() as tmp:
        con = connect(Path(tmp) / "writer.duckdb")
        add_campaign(con, 1, "writer", 7, ImportRecord(imported=f"writer: {args.runs} runs", sha256="none: synthetic"))
        add_reply_codes(con, interface)
        started, cpu = time.perf_counter(), time.process_time()
        for first in range(1, args.runs + 1, BATCH_RUNS):
            last = min(first + BATCH_RUNS, args.runs + 1)
            batch = [(n, None, traces[n % len(traces)], None) for n in range(first, last)]
            with transaction(con):
                insert_traces(con, 1, batch)
        wall, cpu = time.perf_counter() - started, time.process_time() - cpu
        events = event_count(con)
        con.close()
    rate = args.runs / wall
    # the wall clock also counts the commits' waits for the disk, which others on a shared machine slow
    print(f"writer: {args.runs:,} runs ({events:,} events) in {wall:.2f} s ({cpu:.2f} s CPU), batches of {BATCH_RUNS}: "
          f"{rate:,.0f} runs/s ({args.runs / cpu:,.0f} per CPU second), {events / wall:,.0f} events/s; "
          f"{rate / CAMPAIGN_RUNS_S:.1f}x a default campaign's {CAMPAIGN_RUNS_S} runs/s on 2 cores: the writer is "
          f"{'not ' if rate > 2 * CAMPAIGN_RUNS_S else ''}its bottleneck")
    print(f"README: the campaign's writer with a null SUT (`bench/writer_bench.py`) | {rate:,.0f} runs/s "
          f"({args.runs / cpu:,.0f} per CPU second) in batches of {BATCH_RUNS}, {rate / CAMPAIGN_RUNS_S:.1f}x a "
          "default campaign's runs/s | not the bottleneck")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
