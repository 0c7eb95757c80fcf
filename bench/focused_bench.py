"""Finding power per mission second (issue 21): mission seconds spent until every injected defect
and missing protection (bench/defects.py, from the target's layer.toml) is exposed, for random,
targeted (300 mutants, seed 2012) and focused campaigns (--budget 4000s --shrink), on Dala's
genom, bip-a, bip-b and on the manipulator's variants.

random and targeted: the mission seconds of their runs in order (trace id) up to the last first
exposure, shrinking not counted (their campaigns shrink at the end); focused: every run it made,
shrink runs included, until it stopped, and whether each defect has a reproducer of <= 10 steps.

Then the same Dala campaign in real time, at 1x on 8 slots: on the out-of-process simulator
(`sim-*` SUTs of missions/dala/suts.toml), on the ROS layer (`ros-*`, skipped without
`make ros`) and on the ROS 2 lifecycle node (`ros2-*` on Jazzy, skipped without `make ros2`; with
how many nodes were started and the median seconds one took to start and be discovered): its wall minutes, mission seconds, the slots' speed-up (mission s per wall s; 8 at
best), how close the in-process campaign's mission seconds predicted it, whether every
defect was exposed, and where the slots' wall time went (in runs, beyond their mission time, idle; how long 3 or fewer runs, and all 8, were in flight). Figures, not pass or fail: a busy machine gives a smaller speed-up, so the
load average is printed beside them. UNTIMELY_BENCH_REALTIME chooses (default `sim,ros,ros2`; a
comma-separated choice of them, or `none`): each takes about 10 minutes on a 2-core machine.
"""
import os
import subprocess
import sys
import tempfile
import time
from dataclasses import replace
from pathlib import Path

from harness import DEFAULT_MISSION_DIR, ROOT, store
from harness.store import bench_reads
from harness.sut.ros2.environment import installed
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
    rows = bench_reads.findings_in_order(con)
    firsts = [next((r[0] for r in rows if e.matches(*r[1:])), None) for e in wanted]
    shown = [f for f in firsts if f is not None]
    if len(shown) < len(wanted):
        return None, len(shown)
    return bench_reads.test_seconds_until(con, max(shown)), len(shown)


def shown_after(con, wanted) -> str:
    spent, shown = first_exposures(con, wanted)
    return f"{spent:,.0f} mission s" if spent is not None else f"not all: {shown} of {len(wanted)}"


def focused_spent(con) -> tuple[float, str]:
    """Every run's mission seconds (shrink runs are traces too), and why the campaign stopped."""
    return bench_reads.run_totals(con)[1], bench_reads.why_stopped(con)


def compare(folder: Path, name: str, mission: Path, suts: str) -> None:
    wanted = expected(mission, load_mission(mission).properties(), suts.split(","))
    print(f"{name}: {len(wanted)} defects and missing protections on {suts}")
    for strategy in ("random", "targeted"):
        db = folder / f"{name}-{strategy}.duckdb"
        wall = campaign(db, mission, suts, "--strategy", strategy, "--mutants", "300")
        con = store.connect(db, read_only=True)
        total = bench_reads.run_totals(con)[1]
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
    if prefix == "ros" and not (ROOT / ".venv-ros" / "bin" / "python").exists():
        print("ros-* at 1x: skipped, .venv-ros is missing (make ros)")
        return
    if prefix == "ros2" and installed(ROOT, "jazzy"):
        print(f"ros2-* at 1x: skipped, {installed(ROOT, 'jazzy')}")
        return
    variants = TARGETS["dala"][1].split(",")
    suts = ",".join(f"{prefix}-{v}" for v in variants)
    db = folder / f"{prefix}.duckdb"
    load = os.getloadavg()[0]
    wall = campaign(db, DEFAULT_MISSION_DIR, suts, "--strategy", "focused", "--budget", "4000s", "--shrink",
                    "--time-scale", "1", "--jobs", str(SLOTS))
    print(realtime_line(prefix, db, folder / "dala-focused.duckdb", wall, load))


def realtime_line(prefix: str, db: Path, twin: Path, wall: float, load: float) -> str:
    """The figures of a real-time campaign in `db` that took `wall` seconds, the load average
    `load` when it started, beside its in-process twin's mission seconds."""
    con = store.connect(db, read_only=True)
    spent, stopped = focused_spent(con)
    predicted, _ = focused_spent(store.connect(twin, read_only=True))
    variants = TARGETS["dala"][1].split(",")
    in_process = expected(DEFAULT_MISSION_DIR, load_mission(DEFAULT_MISSION_DIR).properties(), variants)
    wanted = [replace(e, sut=f"{prefix}-{e.sut}") for e in in_process]
    missing = [f"{e.sut} {e.what}" for e, r in exposed(con, wanted).items() if r is None]
    runs, beyond = bench_reads.realtime_runs(con)
    return (f"{prefix}-* at 1x on {SLOTS} slots: {wall / 60:.1f} min wall for {spent:,.0f} mission s, stopped "
            f"({stopped}); slots' speed-up {spent / wall:.1f}x real time (of {SLOTS}); in-process prediction "
            f"{predicted:,.0f} mission s ({spent / predicted:.2f}x of it); "
            f"{len(wanted) - len(missing)} of {len(wanted)} defects exposed"
            + (f" (missing: {', '.join(missing)})" if missing else "")
            + f"; {runs} stored runs (golden and tests), median {beyond:.1f} s wall each beyond their mission time"
            + slot_use(con, wall) + discovery(con)
            + f"; load average {load:.1f} before, {os.getloadavg()[0]:.1f} after on {os.cpu_count()} cores")


def slot_use(con, wall: float) -> str:
    """Where the slots' wall time went: in runs (their mission time and beyond it), and idle (a
    round waiting for its slowest run, a shrink for its previous step, the bench between runs)."""
    in_runs, beyond, hung = bench_reads.slot_seconds(con)
    return (f"; the slots spent {in_runs / (SLOTS * wall):.0%} of their wall time in runs ({beyond:,.0f} slot-s "
            f"of it beyond mission time), the rest idle; {hung} runs hung" + in_flight(con))


def in_flight(con) -> str:
    """How long few runs (3 or fewer) and all SLOTS were in flight, from the first run's start to
    the last one's end: the slots' idle time is where few are."""
    rows = bench_reads.run_spans(con)
    edges = sorted([(start, 1) for start, _ in rows] + [(start + wall, -1) for start, wall in rows])
    few = full = 0.0
    running = 0
    for (t, step), (later, _) in zip(edges, edges[1:]):
        running += step
        few += (later - t) * (running <= 3)
        full += (later - t) * (running >= SLOTS)
    return (f"; over the {edges[-1][0] - edges[0][0]:,.0f} s from the first run's start to the last one's end, "
            f"3 or fewer runs in flight for {few:,.0f} s, all {SLOTS} for {full:,.0f} s")


def discovery(con) -> str:
    """How many ROS 2 nodes were started, and the median seconds one took to start and be
    discovered (its adapter's `up in` text)."""
    starts, up = bench_reads.node_starts(con)
    return "" if up is None else f"; {starts} nodes started, each up and discovered in {up:.1f} s (median)"


def realtime_choice() -> list[str]:
    chosen = os.environ.get("UNTIMELY_BENCH_REALTIME", "sim,ros,ros2")
    prefixes = [] if chosen == "none" else chosen.split(",")
    if not set(prefixes) <= {"sim", "ros", "ros2"}:
        raise SystemExit(f"UNTIMELY_BENCH_REALTIME={chosen!r}: give some of sim, ros, ros2 (comma-separated) or none")
    return prefixes


def main() -> None:
    prefixes = realtime_choice()
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        for name, (mission, suts) in TARGETS.items():
            compare(folder, name, mission, suts)
        for prefix in prefixes:
            realtime(folder, prefix)


if __name__ == "__main__":
    main()
