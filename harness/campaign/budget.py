"""A campaign's mission-time budget (`--budget DURATION`) and its stopping rule.

The budget bounds the mission seconds of every run the campaign makes: its traces (traces.sim_s)
and its shrink runs. A test is admitted only if its upper bound (harness.mutator.focused.bound_s)
still fits, so the sum never exceeds the budget.

The stopping rule, per variant: once every aim has been exercised on it, the variant is done
when its last PATIENCE tests showed nothing new (no (property, kind) it had not shown before).
The campaign stops when every variant is done (`rule`), when the next test no longer fits in the
budget (`budget`), or after --mutants tests (`tests`).
"""
from __future__ import annotations

import re
from dataclasses import dataclass, field

from harness.errors import UntimelyError

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


@dataclass
class Budget:
    limit_s: float | None  # None: no budget, only the rule stops the campaign
    spent_s: float = 0.0

    def fits(self, bound: float) -> bool:
        return self.limit_s is None or self.spent_s + bound <= self.limit_s

    def left(self) -> float:
        return float("inf") if self.limit_s is None else self.limit_s - self.spent_s
