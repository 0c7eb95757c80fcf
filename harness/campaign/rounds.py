"""A focused campaign's rounds (harness.campaign.budgeted): ROUND_TESTS tests at a time, the unit
the stopping rule is applied to. Rounds are fixed (test n is in round n // ROUND_TESTS, whatever
--jobs), so a campaign is a function of its arguments, and resumes where it stopped."""
from __future__ import annotations

from concurrent.futures import Future
from dataclasses import dataclass, field

from harness.dispatch.description import Task
from harness.trace import Trace

ROUND_TESTS = 8


@dataclass
class Round:
    """Tests [number * ROUND_TESTS, ...) on the variants active when it was made: the bounds of
    its runs admitted within the budget (by trace id; a trace stored before this session is not
    run again), the test whose runs did not all fit (`cut`), the runs held (made ahead of
    the round before it), its runs in flight, its traces back."""
    number: int
    tests: list[tuple[int, list[Task]]]
    cut: int | None = None
    bounds: dict[int, float] = field(default_factory=dict)
    held: list[Task] = field(default_factory=list)  # made ahead: runs reserved, started once their variant is sure
    pending: dict[Future, Task] = field(default_factory=dict)
    fresh: dict[int, Trace] = field(default_factory=dict)

    @property
    def recorded(self) -> int:
        """How many of its tests the rule takes: those before the cut."""
        return len(self.tests) if self.cut is None else [k for k, _ in self.tests].index(self.cut)

    @property
    def end(self) -> int:
        """The next round's first test."""
        return self.tests[0][0] + self.recorded
