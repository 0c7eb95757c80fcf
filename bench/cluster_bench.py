"""The Dask cluster backend (`campaign --cluster`) against the local pool, on this machine.

1. Simulated runs: the same campaign on the local pool (--jobs 2) and on `--cluster local:2`, of
   100, 400 and 2,000 mutants (the last about the size of the campaign the issue measured, 4,735
   runs); runs/s of each, the median of REPEAT measurements taken in turn, and the cluster's
   ratio to the pool (the coordinator ships every trace back; starting Dask costs a fixed second
   or so, which weighs less on more runs).
2. Real-time runs (the golden mission through `sim-reference` at TIME_SCALE x): spread over 2
   local Dask workers against 1, one slot each.
"""
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from realtime_bench import golden_runs, timed

from harness import ROOT, store
from harness.dispatch.cluster import connect
from harness.store.reads import trace_count

MUTANTS = (100, 400, 2_000)
REPEAT = 3  # a shared 2-core machine's load moves one campaign's runs/s by 5% or more
TIME_SCALE = 20.0
RUNS = 4


def campaign_runs_per_second(mutants: int, *options: str) -> tuple[int, float]:
    """The campaign's runs, and runs/s."""
    with tempfile.TemporaryDirectory() as tmp:
        db = Path(tmp) / "c.duckdb"
        start = time.perf_counter()
        subprocess.run([sys.executable, "-m", "harness", "campaign", "--mutants", str(mutants), "--sut",
                        "genom,bip-a", "--db", str(db), *options], cwd=ROOT, check=True,
                       stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        wall = time.perf_counter() - start
        con = store.connect(db, read_only=True)
        runs = trace_count(con)
        con.close()
    return runs, runs / wall


def realtime_wall(workers: int) -> float:
    setup, tasks = golden_runs(RUNS, TIME_SCALE)
    with connect(f"local:{workers}", setup, workers) as cluster:
        return timed(cluster.run_all, tasks)[0]


def main() -> int:
    ratios = []
    for mutants in MUTANTS:
        pools, dasks = [], []
        for _ in range(REPEAT):  # in turn, so that a busy spell slows both
            runs, rate = campaign_runs_per_second(mutants, "--jobs", "2")
            pools.append(rate)
            dasks.append(campaign_runs_per_second(mutants, "--cluster", "local:2")[1])
        pool, dask = statistics.median(pools), statistics.median(dasks)
        ratios.append(f"{dask / pool:.2f} at {mutants:,} mutants ({runs:,} runs; {dask:.1f} against {pool:.1f} runs/s)")
        print(f"simulated campaign ({mutants:,} mutants, {runs:,} runs on genom,bip-a, start-up and analysis included, "
              f"medians of {REPEAT})")
        print(f"local pool, 2 jobs     {pool:.1f} runs/s")
        print(f"Dask, local:2          {dask:.1f} runs/s  (cluster / pool = {dask / pool:.2f})")
    print(f"README: the Dask cluster beside the local pool, one machine (`bench/cluster_bench.py`) | "
          f"{'; '.join(ratios)}, 2 workers, start-up and analysis included, medians of {REPEAT}; docs/cluster.md "
          "says where the rest goes | ≥ 0.9")
    one, two = realtime_wall(1), realtime_wall(2)
    print(f"real time: {RUNS} golden runs through sim-reference at {TIME_SCALE:g}x")
    print(f"1 Dask worker          {one:.1f} s wall")
    print(f"2 Dask workers         {two:.1f} s wall  (speed-up {one / two:.2f}x)")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
