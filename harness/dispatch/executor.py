"""Where a campaign's runs happen: one protocol, `Executor`. Its `run_all(tasks, on_trace)` runs
every task and calls `on_trace(task, result)` in the calling thread, in completion order; an
UntimelyError from a run (a SUT that cannot be used) stops it. The worker pool
(harness.dispatch.workers.Pool), a Dask cluster (harness.dispatch.cluster.Cluster) and the slots of a
focused campaign on external SUTs (harness.campaign.slots.Slots) are executors; the pool also
runs `campaign --shrink`'s shrinks, a task each."""
from __future__ import annotations

from contextlib import contextmanager
from typing import Callable, Iterator, Protocol

from harness.dispatch.description import Setup, Task
from harness.dispatch.workers import Pool


class Executor(Protocol):
    def run_all(self, tasks: list[Task], on_trace: Callable[[Task, object], None]) -> None:
        """Run every task; `on_trace(task, result)` here, as each finishes."""


@contextmanager
def open_executor(cluster: str | None, setup: Setup, jobs: int) -> Iterator[Executor]:
    """The local pool of `jobs` workers, or a checked Dask cluster (`--cluster ADDRESS`)."""
    if not cluster:
        with Pool(setup, jobs) as pool:
            yield pool
        return
    from harness.dispatch import cluster as dask_cluster  # Dask is an optional dependency
    with dask_cluster.connect(cluster, setup, jobs) as backend:
        yield backend
