"""`campaign --shrink`: shrink the representative trace of every distinct bad behaviour of a
campaign (view bad_behaviours), a task each on a worker pool of its own (harness.dispatch.executor:
the pool that runs the campaign's runs, without their watchdog: a shrink is a chain of runs),
each failure recorded without stopping the others."""
from __future__ import annotations

from dataclasses import dataclass, replace
from pathlib import Path
from typing import Callable

from harness import store
from harness.campaign.context import CampaignContext
from harness.campaign.shrink import Behaviour, Original, Shrunk, original, shrunk, stored
from harness.errors import UntimelyError
from harness.dispatch.description import Setup
from harness.dispatch.workers import Pool
from harness.store import campaign_reads
from harness.store.record import ShrinkRecord, records
from harness.sut import processes
from harness.target.interface import Interface, Property


@dataclass(frozen=True)
class ShrinkTask:
    """One behaviour's shrink, which a pool worker performs as it performs a run."""
    index: int  # its place in the view's order, in which the shrinks are stored
    behaviour: Behaviour
    orig: Original
    properties: list[Property]

    def perform(self, setup: Setup, interface: Interface, slot: int) -> Shrunk:
        try:
            return shrunk(replace(self.orig, slot=slot, runner=setup.runner), self.behaviour, self.properties)
        except Exception as e:  # noqa: BLE001 - one behaviour's failure must not stop the others
            processes.raise_if_stopping()
            return self.crashed(str(e) if isinstance(e, UntimelyError) else f"{type(e).__name__}: {e}")

    def crashed(self, error: str, wall_s: float = 0.0) -> Shrunk:
        return Shrunk(self.orig, None, 0, wall_s, error)


def _stored(con, task: ShrinkTask, result: Shrunk, out: Path) -> str:
    """Store a shrink (its runs, its script; a failure in table shrink_failures); its line."""
    try:
        line = stored(con, task.behaviour, result, out)
    except Exception as e:  # noqa: BLE001 - one behaviour's failure must not stop the others
        processes.raise_if_stopping()  # but a stop that DuckDB made a RuntimeError does
        result = task.crashed(str(e) if isinstance(e, UntimelyError) else f"{type(e).__name__}: {e}")
    if result.error:
        behaviour = task.behaviour
        store.record_shrink_failure(con, task.orig.trace_id, behaviour.sut, behaviour.verdict, behaviour.property_id,
                                    result.error)
        line = f"{behaviour}: not shrunk (table shrink_failures): {result.error}"
    return line


def representatives(ctx: CampaignContext, say: Callable[[str], None]) -> None:
    """`campaign --shrink`: shrink the representative trace of every distinct bad behaviour
    (view bad_behaviours) not shrunk yet, `ctx.jobs` at a time (external SUTs: one at a time);
    this process stores them in the view's order and says one line per behaviour. External SUTs
    run as the campaign's arguments define them, not as the store records them."""
    con = ctx.con
    done = {(s.sut, s.verdict, s.property) for _, _, s in records(con, ShrinkRecord) if s.steps_after is not None}
    mine = ctx.setup.external
    found = [(Behaviour(sut, verdict, property_id), trace_id)
             for sut, property_id, verdict, trace_id in campaign_reads.representatives(con)
             if (sut, verdict, property_id) not in done]
    todo = [ShrinkTask(n, behaviour, replace(original(con, trace_id), external=mine), ctx.properties)
            for n, (behaviour, trace_id) in enumerate(found)]
    results, next_shown = {}, 0

    def in_order(task: ShrinkTask, result: Shrunk) -> None:
        nonlocal next_shown
        results[task.index] = result
        while next_shown in results:
            say(_stored(con, todo[next_shown], results.pop(next_shown), ctx.shrink_to))
            next_shown += 1
    if todo:
        with Pool(replace(ctx.setup, watchdog_s=None), 1 if ctx.setup.external else ctx.jobs) as pool:
            pool.run_all(todo, in_order)
