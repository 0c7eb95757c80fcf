"""Adapters kept between runs: the simulator adapter, a run on a slot, and the census of this
process's children (the adapters it started)."""
import os
from pathlib import Path

from harness.target.suts import ExternalSut
from harness.sut.external.runner import run_external
from harness.target.script import parse

# TrackSpeedStart before the Init: refused on a fresh layer, started on one that kept the last run's Init.
FRESH = """send rflex.TrackSpeedStart as early
wait early
send rflex.Init as ri
wait ri
"""


SIMULATOR = ExternalSut("sim", command="{python} -m harness.sut.simulated --variant reference", time_scale=20.0,
                        startup_s=30.0, probe_timeout_s=3.0)


def run(sut: ExternalSut, interface, body: str = FRESH, slot: int = 0):
    return run_external(parse(body, "short"), sut, 7, interface, slot=slot)


def adapters() -> set[int]:
    """This process's child processes (the adapters it started)."""
    children = set()
    for task in os.listdir(f"/proc/{os.getpid()}/task"):
        try:
            listed = Path(f"/proc/{os.getpid()}/task/{task}/children").read_text()
        except FileNotFoundError:  # a thread that ended since the listing has no children left
            continue
        children |= {int(pid) for pid in listed.split()}
    return children


def codes(trace) -> list[str]:
    return [e[7] for e in trace.events if e[2] == "final"]
