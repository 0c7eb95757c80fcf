"""Test generation (issue 10): random against targeted mutants, and shrinking.

1. Mutants generated per second by each strategy (targeted: with and without running and
   judging the golden, which it needs once).
2. The default campaign size (300 mutants, seed 2012) with each strategy on every variant, side
   by side: requests with the P-condition false per property on `reference` (target: targeted
   >= 30 for each of the 21), and distinct bad behaviours found: (variant, property, FN or FP)
   combinations and hung variants (target: targeted >= random).
3. The time to shrink a typical reproducer: the representative of each hang and of one FN and
   one FP per variant of the targeted campaign (median and max).
"""
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from harness import DEFAULT_MISSION_DIR, ROOT, store
from harness.sut.executive import run_script
from harness.target.interface import load_interface, load_properties
from harness.analysis.judge import Judge
from harness.mutator import operators, targeted
from harness.target.script import load_script
from harness.campaign.shrink import Behaviour, original, shrink
from harness.store.bench_reads import bad_behaviour_keys
from harness.store.sql import render_bench

VARIANTS = "genom,bip-a,bip-b,bare,reference"
MUTANTS, SEED, COVERAGE_TARGET = 300, 2012, 30
STRATEGIES = ("random", "targeted")


def generation_speed():
    interface = load_interface(DEFAULT_MISSION_DIR / "interface.toml")
    properties = load_properties(DEFAULT_MISSION_DIR / "properties.toml", interface)
    golden = load_script(DEFAULT_MISSION_DIR / "golden.mission", interface)
    start = time.perf_counter()
    list(operators.generate(golden, interface, operators.Draw(MUTANTS, SEED)))
    random_s = time.perf_counter() - start
    start = time.perf_counter()
    trace = run_script(golden, "genom", SEED, interface, DEFAULT_MISSION_DIR / "world.toml")
    verdicts = Judge(interface, properties).verdicts([trace])[0]
    golden_s = time.perf_counter() - start
    start = time.perf_counter()
    targeted.generate(targeted.GoldenRun(golden, trace, verdicts), interface, properties,
                      operators.Draw(MUTANTS, SEED, targeted.SITES_PER_MUTANT))
    targeted_s = time.perf_counter() - start
    print(f"random           {MUTANTS / random_s:,.0f} mutants/s")
    print(f"targeted         {MUTANTS / targeted_s:,.0f} mutants/s; {MUTANTS / (targeted_s + golden_s):,.0f} "
          f"mutants/s counting the golden run and its judgement ({golden_s:.2f} s, once per campaign)")


def campaign(db: Path, strategy: str) -> float:
    start = time.perf_counter()
    subprocess.run([sys.executable, "-m", "harness", "campaign", "--strategy", strategy, "--mutants", str(MUTANTS),
                    "--seed", str(SEED), "--sut", VARIANTS, "--db", str(db)],
                   cwd=ROOT, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    return time.perf_counter() - start


def compare(dbs: dict[str, Path]) -> bool:
    cons = {s: store.connect(db, read_only=True) for s, db in dbs.items()}
    covered = {s: con.execute(render_bench("reference_coverage")).fetchall() for s, con in cons.items()}
    print(f"\n{'requests with C false on reference':<46}" + "".join(f"{s:>10}" for s in STRATEGIES))
    for (prop, a), (_, b) in zip(*covered.values()):
        print(f"  {prop:<44}{a:>10}{b:>10}")
    lows = {s: min(n for _, n in rows) for s, rows in covered.items()}
    print(f"  {'minimum':<44}" + "".join(f"{lows[s]:>10}" for s in STRATEGIES))
    found = {s: bad_behaviour_keys(con) for s, con in cons.items()}
    print(f"\n{'distinct bad behaviours':<46}" + "".join(f"{s:>10}" for s in STRATEGIES))
    for sut in VARIANTS.split(","):
        for kind, test in (("FN", lambda b: b[1] == "FN"), ("FP", lambda b: b[1] == "FP"),
                           ("hung", lambda b: b[1] == "hung")):
            print(f"  {sut + ' ' + kind:<44}" + "".join(
                f"{sum(1 for b in found[s] if b[0] == sut and test(b)):>10}" for s in STRATEGIES))
    combos = {s: sum(1 for b in f if b[1] != "hung") for s, f in found.items()}
    hangs = {s: sum(1 for b in f if b[1] == "hung") for s, f in found.items()}
    print(f"  {'(variant, property, FN|FP) combinations':<44}" + "".join(f"{combos[s]:>10}" for s in STRATEGIES))
    print(f"  {'hung variants':<44}" + "".join(f"{hangs[s]:>10}" for s in STRATEGIES))
    only_random = sorted(found["random"] - found["targeted"], key=str)
    if only_random:
        listed = ", ".join(str(Behaviour(sut, verdict, prop)) for sut, verdict, prop in only_random)
        print(f"  found by random only: {listed}")
    for con in cons.values():
        con.close()
    met = lows["targeted"] >= COVERAGE_TARGET and combos["targeted"] >= combos["random"] \
        and hangs["targeted"] >= hangs["random"]
    print(f"\ntargets          {'met' if met else 'NOT met'}: every property >= {COVERAGE_TARGET} C-false requests "
          "on reference with targeted; targeted finds at least as many combinations and hangs as random")
    return met


def shrink_times(db: Path) -> None:
    interface = load_interface(DEFAULT_MISSION_DIR / "interface.toml")
    properties = load_properties(DEFAULT_MISSION_DIR / "properties.toml", interface)
    con = store.connect(db, read_only=True)
    picked = con.execute(render_bench("shrink_picks")).fetchall()
    times, steps = [], []
    for sut, verdict, prop, trace_id in picked:
        orig = original(con, trace_id)
        start = time.perf_counter()
        script, runs, _ = shrink(orig, Behaviour(sut, verdict, prop), properties)
        times.append(time.perf_counter() - start)
        steps.append(len(script.steps))
        print(f"  {str(Behaviour(sut, verdict, prop)):<58} {len(orig.body.splitlines()):>3} -> "
              f"{len(script.steps):>2} steps, {runs:>4} runs, {times[-1]:5.1f} s")
    con.close()
    print(f"shrink           median {statistics.median(times):.1f} s, max {max(times):.1f} s over "
          f"{len(times)} reproducers; at most {max(steps)} steps")


def main() -> int:
    print("== mutants generated per second ==")
    generation_speed()
    with tempfile.TemporaryDirectory() as tmp:
        dbs = {s: Path(tmp) / f"{s}.duckdb" for s in STRATEGIES}
        print(f"\n== default campaign size, {MUTANTS} mutants, seed {SEED}, on {VARIANTS} ==")
        for s, db in dbs.items():
            print(f"{s:<16} campaign in {campaign(db, s):.0f} s")
        compare(dbs)
        print("\n== shrinking a typical reproducer (the most frequent FN, FP and hang per variant) ==")
        shrink_times(dbs["targeted"])
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
