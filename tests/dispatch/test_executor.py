"""One executor abstraction: the worker pool runs any task that can be performed and can say how
it crashed (a campaign's runs, `campaign --shrink`'s shrinks), each result handed back in this
process; a task whose worker dies is recorded as crashed and the others go on."""
import os
from dataclasses import dataclass
from pathlib import Path

from harness import DEFAULT_MISSION_DIR
from harness.dispatch.executor import open_executor
from harness.dispatch import transport
from harness.dispatch.workers import Pool
from harness.target.mission import INTERFACE_FILE, WORLD_FILE


@dataclass(frozen=True)
class Square:
    """A task that is not a run: its worker squares n, or dies on 3."""
    n: int

    def perform(self, setup, interface, slot):
        if self.n == 3:
            os._exit(7)
        return (self.n * self.n, slot, interface.replies["ok"])

    def crashed(self, error, wall_s=0.0):
        return f"crashed: {error}"


def _setup():
    return transport.setup(None, Path(DEFAULT_MISSION_DIR / INTERFACE_FILE), Path(DEFAULT_MISSION_DIR / WORLD_FILE), 0.0)


def test_the_pool_performs_any_task_and_records_a_worker_that_died_as_that_tasks_crash():
    results = {}
    with Pool(_setup(), 2) as pool:
        pool.run_all([Square(n) for n in range(6)], lambda task, result: results.update({task.n: result}))
    assert {n: r[0] for n, r in results.items() if n != 3} == {0: 0, 1: 1, 2: 4, 4: 16, 5: 25}
    assert {r[1] for n, r in results.items() if n != 3} <= {0, 1} and all(r[2] == "T" for n, r in results.items()
                                                                            if n != 3)
    assert results[3] == "crashed: the worker process died (exit code 7) during this run"


def test_without_a_cluster_the_executor_is_the_pool():
    with open_executor(None, _setup(), 1) as executor:
        assert isinstance(executor, Pool)
        done = []
        executor.run_all([Square(5)], lambda task, result: done.append(result[0]))
    assert done == [25]
