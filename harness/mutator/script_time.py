"""How long a script's run lasts in mission time, known before it runs: the bounds by which a
budgeted campaign admits a test (harness/campaign/budget.py) and a campaign checks its budget."""
from __future__ import annotations

from harness.sut.executive import DRAIN_S, REACTION_S
from harness.target.script import Script


def bound_s(script: Script) -> float:
    """The longest a run of a script can last in mission time: its sleeps, its waits' timeouts
    and reactions, and the drain (a hang or crash ends it sooner)."""
    return least_s(script) + DRAIN_S + \
        sum((s.seconds or float("inf")) + REACTION_S for s in script.steps if s.op == "wait")


def least_s(script: Script) -> float:
    """The shortest a run of a script that completes can last in mission time: its sleeps."""
    return sum(s.seconds for s in script.steps if s.op == "sleep")
