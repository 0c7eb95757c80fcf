"""Runs of a campaign across worker processes; a run that fails never stops the others.

A small pool of our own rather than concurrent.futures: the parent knows which run each
worker holds, so when a worker process dies (os._exit, a segfault in a native library, the
OOM killer) exactly that run is recorded as crashed and a fresh worker takes the next one.
An exception escaping the runner is caught in the worker and becomes a crashed trace too.
A run that gives no result within `watchdog_s` of wall time has its worker killed: the
simulator works in virtual time, so that is a bug in it, not a slow mission; a real-time run has
the executive's own watchdogs, so that is a bench that hangs. Each worker is a slot: it keeps its
number (0..jobs-1) for its life, and an external SUT started for one of its runs learns it
(UNTIMELY_SLOT), to pick ports of its own. The clock starts
when the worker is ready (it has imported the project), not when the task is handed out: a
spawned worker takes a second or more to start on a loaded machine.

Workers are spawned (not forked): the parent holds an open DuckDB connection and threads.
They ignore SIGINT, so Ctrl-C reaches the parent alone, which stops them: SIGTERM, on which a
busy worker ends its adapter (harness.sut.processes), then SIGKILL after a grace. A worker whose
parent dies gets SIGTERM too, and leaves quietly.
"""
from __future__ import annotations

import multiprocessing
import signal
import time
from collections import deque
from multiprocessing.connection import wait
from typing import Callable

from harness.errors import UntimelyError
from harness.dispatch.description import Setup, Task
from harness.sut import processes
from harness.sut.external.kept import kept_adapters
from harness.target.interface import load_interface
from harness.trace import Trace

STOP_GRACE_S = 8.0  # a busy worker's adapter may take GRACE_S, then TERM_GRACE_S, to end
READY = "ready"  # a worker's first message: it has set up and can run


def _serve(conn, setup: Setup, slot: int) -> None:
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    processes.stop_on_signals()
    processes.die_with_parent()
    processes.become_subreaper()  # the daemons of its adapters come back to it, to be ended
    try:
        interface = load_interface(setup.interface_file)
        conn.send(READY)
        with kept_adapters():
            while (task := conn.recv()) is not None:
                conn.send(task.perform(setup, interface, slot))
    except (EOFError, OSError, KeyboardInterrupt):  # the parent is gone, or stops this worker
        return


class _Worker:
    def __init__(self, context, setup: Setup, slot: int):
        self.slot = slot
        self.conn, child = context.Pipe()
        self.process = context.Process(target=_serve, args=(child, setup, slot), daemon=True)
        self.process.start()
        child.close()
        self.task: Task | None = None
        self.since = 0.0
        self.ready = False

    def give(self, task: Task) -> None:
        self.task, self.since = task, time.monotonic()
        self.conn.send(task)

    def result(self):
        """The finished run's trace, or None if there is none (yet)."""
        try:
            while self.conn.poll():
                message = self.conn.recv()
                if message != READY:
                    return message
                self.ready, self.since = True, time.monotonic()
        except (EOFError, OSError):
            pass
        return None

    def overdue(self, watchdog_s: float | None) -> bool:
        """Busy past the watchdog, counted from when it was ready (or given its task, if later)."""
        return self.ready and watchdog_s is not None and time.monotonic() - self.since >= watchdog_s

    def death(self) -> str:
        self.process.join(STOP_GRACE_S)
        code = self.process.exitcode
        how = (f"signal {signal.Signals(-code).name}" if code is not None and code < 0
               else f"exit code {code}")
        if not self.ready:  # every run would fail the same way: stop rather than record them all
            raise UntimelyError(f"a worker process exited ({how}) before it could run anything; "
                                "its error output above says why")
        return f"the worker process died ({how}) during this run"

    def terminate(self) -> None:
        """SIGTERM: a busy worker ends its run's adapter, then exits."""
        self.process.terminate()

    def kill(self) -> None:
        """SIGTERM, then SIGKILL if it has not exited after STOP_GRACE_S."""
        self.terminate()
        self.process.join(STOP_GRACE_S)
        self.process.kill()
        self.process.join()


class Pool:
    """`jobs` worker processes, started when first needed and kept across `run_all` calls (a
    campaign's golden runs, then its mutants); stopped when the block ends."""

    def __init__(self, setup: Setup, jobs: int):
        self.setup, self.jobs = setup, jobs
        self.context = multiprocessing.get_context("spawn")
        self.workers: list[_Worker] = []
        self.started = processes.uptime()

    def __enter__(self) -> "Pool":
        return self

    def __exit__(self, *_exception) -> None:
        _stop(self.workers)
        processes.end_orphans(self.started)  # adapters of workers that had to be killed

    def run_all(self, tasks: list[Task], on_trace: Callable[[Task, Trace], None]) -> None:
        """Run every task; `on_trace(task, trace)` is called in this process, in completion order.
        A worker that raises UntimelyError aborts the whole campaign with it; so does any
        exception, after the busy workers are killed."""
        setup, jobs, workers = self.setup, self.jobs, self.workers
        pending = deque(tasks)
        try:
            while pending or any(w.task for w in workers):
                while pending and len(workers) < jobs:
                    free = min(set(range(jobs)) - {w.slot for w in workers})
                    workers.append(_Worker(self.context, setup, free))
                for worker in workers:
                    if worker.task is None and pending:
                        worker.give(pending.popleft())
                busy = [w for w in workers if w.task]
                wait([w.conn for w in busy] + [w.process.sentinel for w in busy], timeout=1.0)
                for worker in busy:
                    alive = worker.process.is_alive()  # before reading: a dead worker's result is all in the pipe
                    result = worker.result()
                    if result is None and alive:
                        if not worker.overdue(setup.watchdog_s):
                            continue
                        worker.kill()
                        result = worker.task.crashed(f"no result after {setup.watchdog_s:g} s of wall time; "
                                                     "the worker was killed", setup.watchdog_s)
                    elif result is None:
                        result = worker.task.crashed(worker.death())
                    if isinstance(result, UntimelyError):
                        raise result
                    task, worker.task = worker.task, None
                    if not worker.process.is_alive():
                        workers.remove(worker)
                    on_trace(task, result)
        except BaseException:
            _stop(workers)
            workers.clear()
            raise


def run_all(tasks: list[Task], setup: Setup, jobs: int, on_trace: Callable[[Task, Trace], None]) -> None:
    """Run every task on a pool of `jobs` workers of its own (see Pool.run_all)."""
    with Pool(setup, jobs) as pool:
        pool.run_all(tasks, on_trace)


def _stop(workers: list[_Worker]) -> None:
    """Idle workers leave on their own; busy ones (Ctrl-C, an error) are told to stop (SIGTERM)."""
    for worker in workers:
        if worker.task:
            worker.terminate()
        else:
            try:
                worker.conn.send(None)
            except OSError:
                pass
    deadline = time.monotonic() + STOP_GRACE_S
    for worker in workers:
        worker.process.join(max(0.0, deadline - time.monotonic()))
        if worker.process.is_alive():
            worker.process.kill()
            worker.process.join()
