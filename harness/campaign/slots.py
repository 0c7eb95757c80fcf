"""The slots of a focused campaign on external SUTs, shared by its test runs and its shrink runs.

A real-time run mostly waits, on its SUT and on the clock. A round of tests waits for its slowest
run, and shrinking a finding is a chain of runs one after another: with rounds and shrinks
taking turns, most of the slots idled (the out-of-process simulator at 1x on 8 slots gave 1.8x
real time). Here a run, a test's or a shrink's, holds a slot only while it runs, shrinks go on
in the background while later rounds run, and the next round's runs may be started while a
round's tail runs (harness.campaign.budgeted). A free slot goes to the waiting run of lowest
rank: a test's is its round's number, every shrink's `shrink_rank` (set by the campaign between
the round in flight and the one started ahead of it: a shrink, a chain, is not kept waiting
behind a round that the stopping rule does not wait for yet). Without ranks, tests come first.

Runs are played in daemon threads of the campaign's process, as shrink runs always were: an
external run's work is its adapter's, the bench only stamps and forwards lines. A campaign
stopped by an error or Ctrl-C does not wait for them: an adapter whose bench exits sees the end
of its input and exits. In process, runs are CPU-bound and rounds and shrinks keep their order
(reproducibility), so this is used only when every variant is external.
"""
from __future__ import annotations

import threading
from concurrent.futures import Future, as_completed
from contextlib import contextmanager
from typing import Callable, Iterator

from harness.errors import InternalSignal, UntimelyError
from harness.campaign.context import CampaignContext
from harness.dispatch.description import Setup, Task
from harness.trace import Trace


class SlotsClosed(InternalSignal):
    """The campaign stopped: a shrink waiting for a slot gives up."""


class Slots:
    def __init__(self, setup: Setup, interface, jobs: int):
        self.setup, self.interface = setup, interface
        self.free = list(range(jobs - 1, -1, -1))  # slot 0 first, as the worker pool hands them out
        self.turn = threading.Condition()
        self.waiting: list[float | None] = []  # the ranks of the runs waiting for a slot; None: a shrink's
        self.shrink_rank = float("inf")
        self.closed = False

    @contextmanager
    def taken(self, rank: float | None = None) -> Iterator[int]:
        """A free slot's number while the block runs, given to the waiting run of lowest rank (a
        test's `rank`; None: a shrink's, `shrink_rank`)."""
        with self.turn:
            self.waiting.append(rank)
            try:
                self.turn.wait_for(lambda: self.closed or (self.free and self._first(rank)))
            finally:
                self.waiting.remove(rank)
            if self.closed:
                raise SlotsClosed()
            slot = self.free.pop()
        try:
            yield slot
        finally:
            with self.turn:
                self.free.append(slot)
                self.turn.notify_all()

    def _first(self, rank: float | None) -> bool:
        ranks = [self.shrink_rank if r is None else r for r in self.waiting]
        return (self.shrink_rank if rank is None else rank) <= min(ranks)

    def submit(self, tasks: list[Task], rank: float = 0) -> dict[Future, Task]:
        """The tasks' runs started, each waiting for a slot at `rank`; each future's result is a
        Trace, or the UntimelyError of an adapter that cannot be started."""
        return {self.background(self._run, task, rank): task for task in tasks}

    def run_all(self, tasks: list[Task], on_trace: Callable[[Task, Trace], None]) -> None:
        """An executor (harness.dispatch.executor) on these slots: `on_trace` in this thread, in completion order;
        an UntimelyError (an adapter that cannot be started) stops the campaign."""
        futures = self.submit(tasks)
        for future in as_completed(futures):
            on_trace(futures[future], traced(future))

    def _run(self, task: Task, rank: float) -> Trace | UntimelyError:
        with self.taken(rank) as slot:
            return self.setup.run(task, self.interface, slot)

    @staticmethod
    def background(work: Callable, *args) -> Future:
        """`work(*args)` in a daemon thread of its own."""
        future = Future()

        def body() -> None:
            try:
                future.set_result(work(*args))
            except BaseException as e:  # noqa: BLE001 - handed to whoever reads the future
                future.set_exception(e)
        threading.Thread(target=body, daemon=True).start()
        return future

    def close(self) -> None:
        with self.turn:
            self.closed = True
            self.turn.notify_all()


def at_once(work, *args) -> Future:
    """`work(*args)` run now, as a finished future (in process, shrinks keep the rounds' order)."""
    future = Future()
    future.set_result(work(*args))
    return future


def traced(future: Future) -> Trace:
    """A finished run's trace; an adapter that could not be started stops the campaign."""
    result = future.result()
    if isinstance(result, UntimelyError):
        raise result
    return result


@contextmanager
def campaign_slots(ctx: CampaignContext) -> Iterator[Slots | None]:
    """Slots for a focused campaign whose variants are all external and run here (not on a
    cluster); None otherwise."""
    if ctx.cluster or not set(ctx.config.sut) <= set(ctx.config.external):
        yield None
        return
    slots = Slots(ctx.setup, ctx.interface, ctx.jobs)
    try:
        yield slots
    finally:
        slots.close()
