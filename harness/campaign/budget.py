"""A campaign's mission-time budget (`--budget DURATION`) and its stopping rule.

The budget bounds the mission seconds of every run the campaign makes: its traces (traces.sim_s)
and its shrink runs. A test is admitted only if its upper bound (harness.mutator.script_time.bound_s)
still fits, so the sum never exceeds the budget.

The stopping rule, per variant: once every aim has been exercised on it, the variant is done
when its last PATIENCE tests showed nothing new (no (property, kind) it had not shown before).
The campaign stops when every variant is done (`rule`), when the next test no longer fits in the
budget once the runs before it are back and have said what they took (`budget`), or after
--mutants tests (`tests`).
"""
from __future__ import annotations

import re
import threading
from contextlib import nullcontext
from dataclasses import dataclass, field

from harness.campaign import shrink
from harness.campaign.slots import Slots
from harness.errors import BudgetSpent, UntimelyError
from harness.progress import Progress
from harness.store.campaign_reads import spent_s

UNITS = {"s": 1.0, "m": 60.0, "h": 3600.0}
DURATION = re.compile(r"(\d+(?:\.\d+)?)([smh])$")
RULE = "every aim exercised, then {patience} tests per variant without a new (property, kind)"


def parse_duration(text: str) -> float:
    """Seconds from `4000s`, `40m`, `1.5h`."""
    found = DURATION.match(text.strip())
    if not found or not 0 < float(found.group(1)) * UNITS[found.group(2)] < float("inf"):
        raise UntimelyError(f"--budget {text!r}: give mission time as a positive number followed by s, m or h "
                            "(4000s, 40m, 1h)")
    return float(found.group(1)) * UNITS[found.group(2)]


@dataclass
class VariantState:
    """What one variant has shown so far, in test order."""
    tests: int = 0
    quiet: int = 0  # tests since the last one that showed something new
    shown: set = field(default_factory=set)  # (property_id, kind)
    done: bool = False

    def record(self, found: set, aims: int, patience: int) -> set:
        """One test's findings; returns those new on this variant and applies the rule."""
        new = found - self.shown
        self.shown |= new
        self.tests += 1
        self.quiet = 0 if new else self.quiet + 1
        self.done = self.tests >= aims and self.quiet >= patience
        return new

    def stays_active(self, tests: int, aims: int, patience: int) -> bool:
        """Whether the rule cannot end this variant within its next `tests` tests, whatever they show."""
        return self.tests + tests < aims or self.quiet + tests < patience


@dataclass
class Budget:
    """What a campaign has spent, runs in flight counted at their bounds until they say what they
    took; read and changed under `account` (shrinks run in the background), whose waiters a
    settled run wakes."""
    limit_s: float | None  # None: no budget, only the rule stops the campaign
    spent_s: float = 0.0
    in_flight: int = 0  # runs reserved at their bounds and not yet settled
    account: threading.Condition = field(default_factory=threading.Condition, repr=False)

    def fits(self, bound: float) -> bool:
        return self.limit_s is None or self.spent_s + bound <= self.limit_s

    def reserve(self, bound: float) -> None:
        self.spent_s += bound
        self.in_flight += 1

    def settle(self, bound: float, took: float) -> None:
        """A reserved run came back having taken `took` mission seconds (0: it never started); the
        caller holds `account`."""
        self.spent_s += took - bound
        self.in_flight -= 1
        self.account.notify_all()

    def left(self) -> float:
        return float("inf") if self.limit_s is None else self.limit_s - self.spent_s


@dataclass
class MeteredOriginal(shrink.Original):
    """A trace to shrink whose re-runs are counted against the campaign's budget (shrinks run
    side by side, under the budget's account), each on a slot taken for that run alone. A run
    that does not fit waits while other runs are in flight at their bounds (they mostly take far
    less): the budget is spent only when nothing is left to come back."""
    budget: Budget | None = None
    bound: float = 0.0  # no candidate outlasts the original script's bound
    slots: Slots | None = None  # None: in process, on slot 0

    def run(self, body: str):
        with self.budget.account:
            while not self.budget.fits(self.bound):
                if not self.budget.in_flight:
                    raise BudgetSpent()
                self.budget.account.wait()
            self.budget.reserve(self.bound)
        took = self.bound  # kept counted if the run fails
        try:
            with self.slots.taken() if self.slots else nullcontext(self.slot) as self.slot:
                trace = super().run(body)
            took = trace.sim_s
        finally:
            with self.budget.account:
                self.budget.settle(self.bound, took)
        return trace


def progress(con, campaign_id: int, budget_s: float | None) -> Progress:
    """A focused campaign's bar: the mission seconds of its budget, from what it has spent (a
    resumed campaign's included); without a budget, the runs it makes (the rule's end is not known)."""
    if budget_s is None:
        return Progress(None)
    traces_s, shrink_s = spent_s(con, campaign_id)
    return Progress(budget_s, traces_s + shrink_s, unit="mission s", mission_time=True)
