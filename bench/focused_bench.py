"""Finding power per mission second (issue 21): mission seconds spent until every injected defect
and missing protection (bench/defects.py, from the target's layer.toml) is exposed, for random,
targeted (300 mutants, seed 2012) and focused campaigns (--budget 4000s --shrink), on Dala's
genom, bip-a, bip-b and on the manipulator's variants.

random and targeted: the mission seconds of their runs in order (trace id) up to the last first
exposure, shrinking not counted (their campaigns shrink at the end); focused: every run it made,
shrink runs included, until it stopped, and whether each defect has a reproducer of <= 10 steps.

UNTIMELY_BENCH_REALTIME=sim (or ros, or sim,ros): also the wall time of the focused campaign on
the out-of-process simulator (`sim-*` SUTs) or the ROS layer (`ros-*`, needs `make ros`) at 1x
on 8 slots, and how close the in-process campaign's mission time predicts it.
"""
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from harness import DEFAULT_MISSION_DIR, ROOT, store
from harness.target.mission import load_mission

sys.path.insert(0, str(Path(__file__).resolve().parent))
from defects import expected, exposed  # noqa: E402

TARGETS = {"dala": (DEFAULT_MISSION_DIR, "genom,bip-a,bip-b"),
           "manipulator": (ROOT / "missions" / "manipulator", "safe,careless,quirky,stuck")}
SLOTS = 8


def campaign(db: Path, mission: Path, suts: str, *options: str) -> float:
    start = time.perf_counter()
    subprocess.run([sys.executable, "-m", "harness", "campaign", "--mission", str(mission), "--sut", suts,
                    "--db", str(db), *options], check=True, stdout=subprocess.DEVNULL)
    return time.perf_counter() - start


def first_exposures(con, wanted) -> tuple[float | None, int]:
    """Mission seconds of the runs up to the last first exposure (None if one never shows), and
    how many of `wanted` show at all."""
    rows = con.execute("select trace_id, sut, property_id, kind from trace_findings order by trace_id").fetchall()
    firsts = [next((r[0] for r in rows if e.matches(*r[1:])), None) for e in wanted]
    shown = [f for f in firsts if f is not None]
    if len(shown) < len(wanted):
        return None, len(shown)
    return con.execute("select sum(sim_s) from traces anti join shrink_runs using (trace_id) where trace_id <= ?",
                       [max(shown)]).fetchone()[0], len(shown)


def shown_after(con, wanted) -> str:
    spent, shown = first_exposures(con, wanted)
    return f"{spent:,.0f} mission s" if spent is not None else f"not all: {shown} of {len(wanted)}"


def focused_spent(con) -> tuple[float, str]:
    """Every run's mission seconds (shrink runs are traces too), and why the campaign stopped."""
    traces = con.execute("select sum(sim_s) from traces").fetchone()[0]
    return traces, con.execute("select stopped from campaign_budgets").fetchone()[0]


def compare(folder: Path, name: str, mission: Path, suts: str) -> None:
    wanted = expected(mission, load_mission(mission).properties(), suts.split(","))
    print(f"{name}: {len(wanted)} defects and missing protections on {suts}")
    for strategy in ("random", "targeted"):
        db = folder / f"{name}-{strategy}.duckdb"
        wall = campaign(db, mission, suts, "--strategy", strategy, "--mutants", "300")
        con = store.connect(db, read_only=True)
        total = con.execute("select sum(sim_s) from traces").fetchone()[0]
        print(f"  {strategy:<9} every defect shown after {shown_after(con, wanted)} (campaign {total:,.0f} mission s, "
              f"{wall:.0f} s wall in process; shrinking not counted)")
    db = folder / f"{name}-focused.duckdb"
    wall = campaign(db, mission, suts, "--strategy", "focused", "--budget", "4000s", "--shrink")
    con = store.connect(db, read_only=True)
    spent, stopped = focused_spent(con)
    found = exposed(con, wanted)
    missing = [f"{e.sut} {e.what}" for e, r in found.items() if r is None]
    steps = max((r[1] for r in found.values() if r), default=0)
    print(f"  focused   every defect shown after {shown_after(con, wanted)} (shrinking not counted); "
          f"stopped ({stopped}) after {spent:,.0f} mission s, shrinking included "
          f"({wall:.0f} s wall in process); {len(wanted) - len(missing)} of {len(wanted)} exposed with a "
          f"reproducer of <= 10 steps (largest {steps})" + (f"; missing: {', '.join(missing)}" if missing else ""))


def realtime(folder: Path, prefix: str) -> None:
    """The focused Dala campaign on `prefix`-* SUTs at 1x, 8 slots, against its in-process twin."""
    suts = ",".join(f"{prefix}-{v}" for v in TARGETS["dala"][1].split(","))
    db = folder / f"{prefix}.duckdb"
    wall = campaign(db, DEFAULT_MISSION_DIR, suts, "--strategy", "focused", "--budget", "4000s", "--shrink",
                    "--time-scale", "1", "--jobs", str(SLOTS))
    con = store.connect(db, read_only=True)
    spent, stopped = focused_spent(con)
    twin = store.connect(folder / "dala-focused.duckdb", read_only=True)
    predicted, _ = focused_spent(twin)
    print(f"{prefix}-* at 1x on {SLOTS} slots: stopped ({stopped}) after {spent:,.0f} mission s in {wall / 60:.1f} "
          f"min wall ({spent / wall:.1f}x real time, the slots' speed-up); in process: {predicted:,.0f} mission s "
          f"({spent / predicted:.2f}x of the prediction)")


def main() -> None:
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        for name, (mission, suts) in TARGETS.items():
            compare(folder, name, mission, suts)
        for prefix in filter(None, os.environ.get("UNTIMELY_BENCH_REALTIME", "").split(",")):
            realtime(folder, prefix)


if __name__ == "__main__":
    main()
