"""Speed of the simulated layer: the golden mission on every variant, simulated s / wall s.

Target (issue 2, raised by issue 14): at least 5,000x faster than real time on one core. The figure depends on how
busy the machine is, so it is also printed relative to the calibration loop timed in the same run
(calibration.py); a miss is reported, never a failure of `make bench`.

Each variant first runs the mission once unmeasured (seed 0): the first run in a process pays for
imports, parsing the mission's files and warming Python's caches, which a campaign pays once for
hundreds of runs. Then each seed runs on every variant in turn, so that a burst of load from
elsewhere slows all variants alike; a variant's figures are medians over its seeds, each run's
speed-up its own simulated s over its own wall s (the seed changes the message delays, and so a
little the simulated length).
"""
import statistics
import time

from calibration import calibrate

from harness import DEFAULT_MISSION_DIR
from harness.sut.executive import run_script
from harness.target.interface import load_interface
from harness.target.script import load_script

REPEATS = 9
TARGET = 5000
VARIANTS = ("reference", "genom", "bip-a", "bip-b", "bare")


def main() -> int:
    interface = load_interface(DEFAULT_MISSION_DIR / "interface.toml")
    script = load_script(DEFAULT_MISSION_DIR / "golden.mission", interface)
    world = DEFAULT_MISSION_DIR / "world.toml"
    runs = {sut: [] for sut in VARIANTS}  # (trace, wall s) of each measured run
    before = calibrate()
    for sut in VARIANTS:
        run_script(script, sut, 0, interface, world)  # warm-up, unmeasured (see above)
    for seed in range(REPEATS):
        for sut in VARIANTS:
            start = time.perf_counter()
            trace = run_script(script, sut, seed, interface, world)
            runs[sut].append((trace, time.perf_counter() - start))
    slowest = None  # (speed-up, median wall s) of the slowest variant
    print(f"{'variant':<10} {'outcome':<10} {'sim s':>8} {'wall ms':>9} {'speed-up':>10} {'events/s':>10}")
    for sut, measured in runs.items():
        speed = statistics.median(trace.sim_s / wall for trace, wall in measured)
        wall = statistics.median(wall for _, wall in measured)
        if slowest is None or speed < slowest[0]:
            slowest = (speed, wall)
        print(f"{sut:<10} {measured[-1][0].outcome:<10} {statistics.median(t.sim_s for t, _ in measured):8.1f} "
              f"{wall * 1000:9.1f} {speed:9,.0f}x {statistics.median(len(t.events) / w for t, w in measured):10,.0f}")
    calibration = (before + calibrate()).wall_s  # loops timed before and after the runs, as they ran
    speed, wall = slowest
    verdict = "meets" if speed >= TARGET else "misses"
    print(f"slowest variant: {speed:,.0f}x real time ({verdict} the {TARGET:,}x target; medians of {REPEATS} seeds, "
          f"after one unmeasured warm-up run per variant)")
    print(f"calibration loop {calibration * 1000:.0f} ms (median of the loops before and after); slowest variant's golden run = "
          f"{wall / calibration:.3f} calibration loops (lower is faster; compares across machines and loads)")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
