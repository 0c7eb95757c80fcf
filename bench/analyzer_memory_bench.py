"""Memory of the analysis: the peak resident size of `python -m harness analyze` on synthetic stores
of growing size (built as in analyzer_bench.py), each judged in a fresh process. The growth per
event between the sizes says how large a store one machine judges (docs/analyzer.md). Not a test:

    .venv/bin/python bench/analyzer_memory_bench.py [--events 1000000,2000000,4000000]
"""
from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
from pathlib import Path

from analyzer_bench import synthesise, traces_for

from harness import DEFAULT_MISSION_DIR, ROOT
from harness.target.interface import load_interface
from harness.store.database import connect

REQUESTS = 100  # per trace, as analyzer_bench's large store


def peak_rss_mb(argv: list[str]) -> float:
    """Run a command; the peak resident set size of its process, in MB."""
    child = subprocess.Popen(argv, cwd=ROOT, stdout=subprocess.DEVNULL)
    _, status, usage = os.wait4(child.pid, 0)
    if status:
        raise SystemExit(f"{' '.join(argv)} failed with status {status}")
    return usage.ru_maxrss / 1024  # Linux reports kB


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--events", default="1000000,2000000,4000000", help="store sizes, comma-separated")
    p.add_argument("--seed", type=int, default=2012)
    args = p.parse_args()
    interface = load_interface(DEFAULT_MISSION_DIR / "interface.toml")
    measured = []
    with tempfile.TemporaryDirectory() as tmp:
        for wanted in (int(n) for n in args.events.split(",")):
            db = Path(tmp) / f"store-{wanted}.duckdb"
            con = connect(db)
            events = synthesise(con, interface, traces_for(wanted, REQUESTS), REQUESTS, args.seed)
            con.close()
            # a synthetic store records no target folder: its properties are named
            rss = peak_rss_mb([sys.executable, "-m", "harness", "analyze", "--db", str(db),
                               "--properties", str(DEFAULT_MISSION_DIR / "properties.toml")])
            measured.append((events, rss))
            print(f"{events:>12,} events: peak {rss:,.0f} MB, {rss * 2**20 / events:,.0f} bytes per event in all")
            db.unlink()
    (small, small_rss), (large, large_rss) = measured[0], measured[-1]
    slope = (large_rss - small_rss) * 2**20 / (large - small)
    ram = os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES")
    print(f"growth           {slope:,.0f} bytes per event from {small:,} to {large:,} events "
          f"(fixed part {small_rss - slope * small / 2**20:,.0f} MB)")
    print(f"this machine     {ram / 2**30:,.1f} GB of RAM: about {ram / slope / 1e6:,.0f} million events "
          "at that growth")
    print(f"README: analysis memory (`bench/analyzer_memory_bench.py`) | linear, about {slope:,.0f} bytes per event "
          f"over {small_rss - slope * small / 2**20:,.0f} MB | linear")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
