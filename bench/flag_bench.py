"""The suspicious flag against the ground truth, and the speed of a re-analysis with its diff.

On the default campaign (300 mutants; genom, bip-a, bip-b) and on a --time-mutations campaign
with all five variants, prints the flag's recall (inverted verdicts it flags / inverted
verdicts, target 100%) and precision (inverted verdicts among the flagged: no longer a target since
the alternatives became complete, which raises the flag on every omega of a hung trace whose reply
may have been lost, docs/analyzer.md), against the `inversions` view; and the wall time of
re-analysing the default campaign with the diff of the two analyses (target < 3 s), as a ratio
to the target, and the README's rows of these figures. Campaigns are built in a
temporary folder unless given. Not a test:

    .venv/bin/python bench/flag_bench.py [--default STORE] [--time-mutations STORE]
"""
from __future__ import annotations

import argparse
import contextlib
import io
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from harness import DEFAULT_EPSILON_S, DEFAULT_MISSION_DIR  # noqa: E402
from harness.analysis import diff  # noqa: E402
from harness.analysis.analyzer import materialise  # noqa: E402
from harness.analysis.summary import flag_accuracy  # noqa: E402
from harness.cli import main as cli  # noqa: E402
from harness.target.interface import load_interface, load_properties  # noqa: E402
from harness.store.database import connect  # noqa: E402

CAMPAIGNS = {"default": [], "time-mutations": ["--time-mutations", "--sut", "genom,bip-a,bip-b,bare,reference"]}
ROWS = {"default": "suspicious flag vs. ground truth, default campaign",
        "time-mutations": "suspicious flag, `--time-mutations`, all five variants"}  # the README's
RECALL, REANALYSIS_S = 1.0, 3.0


def campaign(folder: Path, name: str) -> Path:
    db = folder / f"{name}.duckdb"
    started = time.perf_counter()
    with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(io.StringIO()):
        if cli(["campaign", "--db", str(db), *CAMPAIGNS[name]]) != 0:
            raise SystemExit(f"the {name} campaign failed")
    print(f"{name}: campaign built in {time.perf_counter() - started:.0f} s", flush=True)
    return db


def report(name: str, db: Path) -> None:
    interface = load_interface(DEFAULT_MISSION_DIR / "interface.toml")
    properties = load_properties(DEFAULT_MISSION_DIR / "properties.toml", interface)
    con = connect(db)
    materialise(con, properties, DEFAULT_EPSILON_S, interface, DEFAULT_MISSION_DIR / "properties.toml")
    started, cpu = time.perf_counter(), time.process_time()
    materialise(con, properties, DEFAULT_EPSILON_S, interface, DEFAULT_MISSION_DIR / "properties.toml")
    diff.changes(con)
    seconds, cpu = time.perf_counter() - started, time.process_time() - cpu
    judged, inverted, caught, flagged = flag_accuracy(con)
    recall, precision = caught / inverted if inverted else 1.0, caught / flagged if flagged else 1.0
    print(f"{name}: {judged} verdicts, {inverted} inverted, {flagged} flagged, {caught} inverted and flagged")
    print(f"  recall    {100 * recall:5.1f}%  (target >= {100 * RECALL:.0f}%: "
          f"{'met' if recall >= RECALL else 'NOT met'})")
    print(f"  precision {100 * precision:5.1f}%")
    print(f"  re-analysis with diff {seconds:.2f} s wall = {seconds / REANALYSIS_S:.2f} x the {REANALYSIS_S:g} s "
          f"target ({cpu:.2f} s of CPU; other jobs on the machine stretch the wall time)")
    print(f"README: {ROWS[name]} | recall {100 * recall:.1f}%, precision {100 * precision:.1f}% ({inverted} inverted, "
          f"{flagged} flagged; precision is no longer the aim: docs/analyzer.md, \"Against the ground truth\") | "
          f"recall {100 * RECALL:.0f}%")
    if name == "default":
        print(f"README: re-analysis of the default campaign with the diff (`bench/flag_bench.py`) | {seconds:.2f} s "
              f"wall, {cpu:.2f} s CPU | < {REANALYSIS_S:g} s", flush=True)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    for name in CAMPAIGNS:
        parser.add_argument(f"--{name}", type=Path, help=f"an existing store of the {name} campaign")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as folder:
        for name in CAMPAIGNS:
            given = getattr(args, name.replace("-", "_"))
            report(name, given if given else campaign(Path(folder), name))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
