"""Which run a Dask worker was running when it died (harness.dispatch.cluster): a batch of runs
announces each one before it begins it, and after a `KilledWorker` the coordinator reads what the
dead worker's batch announced; its last one is the run that died.

When every worker is a process of this machine (`local:N`), a batch appends each trace id to a
file of its own in a folder the campaign made: a write that returned outlives the process that
made it, and costs no round trip to the scheduler (one per run, 2 to 3% of a simulated campaign's
wall time on 2 cores). Workers on other machines announce on a Dask queue, which the scheduler
holds once `put` returns, and which the campaign drops from the scheduler as it ends. The queue
goes by name: the scheduler unpickles a task's arguments, and a Queue unpickled there would call
the scheduler from its own event loop.
"""
from __future__ import annotations

import os
import tempfile
import uuid
from collections import deque
from contextlib import contextmanager, suppress
from dataclasses import dataclass
from pathlib import Path
from typing import Callable, Iterator

from harness.dispatch.description import Task, crashed


@dataclass(frozen=True)
class Announcements:
    """Where one campaign's batches announce their runs: `folder` (a file per batch) or `queue`
    (the name of a Dask queue, every batch's announcements in it)."""
    folder: str | None = None
    queue: str | None = None

    @contextmanager
    def opened(self, batch: str) -> Iterator[Callable[[int], object]]:
        """On a worker: what announces each trace id of the batch named `batch`."""
        if self.folder is None:
            from distributed import Queue
            yield Queue(self.queue).put
            return
        file = os.open(Path(self.folder) / batch, os.O_WRONLY | os.O_CREAT | os.O_APPEND, 0o600)
        try:
            yield lambda trace_id: os.write(file, b"%d\n" % trace_id)
        finally:
            os.close(file)

    def read(self, batch: str, client) -> list[int]:
        """In the coordinator, after the batch named `batch` failed: the trace ids it announced,
        in order (from the queue: with those of other batches not read before)."""
        if self.folder is None:
            from distributed import Queue
            return Queue(self.queue, client=client).get(batch=True)
        path = Path(self.folder) / batch
        return [int(line) for line in path.read_text().split()] if path.exists() else []


@contextmanager
def announcements(client, local: bool) -> Iterator[Announcements]:
    """A campaign's announcements (a folder of this machine when its workers are `local`), removed
    when it ends."""
    if local:
        with tempfile.TemporaryDirectory(prefix="untimely-announcements-") as folder:
            yield Announcements(folder=folder)
        return
    from distributed import Queue
    queue = Queue(f"untimely-started-{uuid.uuid4().hex}", client=client)
    try:
        yield Announcements(queue=queue.name)
    finally:
        with suppress(OSError, TimeoutError):  # a scheduler gone (maybe why we leave) holds nothing more
            client.run_on_scheduler(_drop_queue, queue.name)


def _drop_queue(name: str, dask_scheduler) -> None:
    """On the scheduler: forget the queue `name`, which it keeps while some handle on it is open
    (each batch opens one, and a dead worker's is never closed)."""
    queues = dask_scheduler.extensions["queues"]
    while name in queues.queues:
        queues.release(name=name)


def failed_batch(batch: list[Task], error: BaseException, announced: set[int], pending: deque) -> list[tuple]:
    """A batch whose task failed. A worker that dies (`KilledWorker`) takes with it the run it
    was running, the batch's last one announced, which is recorded crashed; the runs after it
    never ran and those before it lost their traces with the worker: they go back to the front
    of `pending`, their announcements forgotten (they will make new ones); if it announced none,
    they all go back. Any other failure crashes the whole batch."""
    from distributed import KilledWorker
    culprits = batch
    if isinstance(error, KilledWorker):
        culprits = [task for task in batch if task.trace_id in announced][-1:]
        again = [task for task in batch if task not in culprits]
        announced.difference_update(task.trace_id for task in again)
        pending.extendleft(reversed(again))
    reason = f"the Dask worker running it failed: {type(error).__name__}: {error}"
    return [(task, crashed(task, reason)) for task in culprits]
