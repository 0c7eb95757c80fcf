"""A run's description, as every executor sends it: a `Task` (one script on one SUT, with its seed
and the trace id it makes) and the `Setup` every run of a campaign shares, sent once to each
worker. Its own module, below the worker pool, the Dask cluster and the transports that read it
(harness.dispatch.transport makes a Setup, with the kinds of SUT it knows).
"""
from __future__ import annotations

import time
import traceback
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable

from harness.errors import UntimelyError
from harness.target.suts import ExternalSut
from harness.target.script import parse
from harness.trace import Trace


@dataclass(frozen=True)
class Task:
    """One run. A pool worker performs any task with `perform` and `crashed` (a shrink is one too:
    harness.campaign.representatives)."""
    trace_id: int
    script_id: int
    sut: str
    seed: int
    body: str

    def perform(self, setup: Setup, interface, slot: int) -> Trace | UntimelyError:
        return setup.run(self, interface, slot)

    def crashed(self, error: str, wall_s: float = 0.0) -> Trace:
        return crashed(self, error, wall_s)


@dataclass(frozen=True)
class Setup:
    """What every run of a campaign shares; made by harness.dispatch.transport.setup."""
    runner: Callable  # run_script's signature: (script, sut, seed, interface, world_file, max_delay)
    interface_file: Path
    world_file: Path
    max_delay: float
    external: dict[str, ExternalSut] = field(default_factory=dict)  # SUTs run over untimely/1
    watchdog_s: float | None = None  # wall seconds a run may take before its worker is killed
    # the kinds of SUT as the making process knows them (the transports' registry, in its order),
    # sent with the setup to the workers: each takes a SUT's name and this setup, and returns its
    # transport or None
    kinds: tuple[Callable, ...] = field(kw_only=True)

    def transport(self, name: str):
        """The transport (harness.dispatch.transport.Transport) that runs SUT `name`: the first of
        `kinds` to take it."""
        return next(t for t in (make(name, self) for make in self.kinds) if t is not None)

    def run(self, task: Task, interface, slot: int) -> Trace | UntimelyError:
        """One run, wherever it happens (a pool worker, a Dask worker); never raises."""
        start = time.perf_counter()
        try:
            script = parse(task.body, script_label(task.script_id))
            return self.transport(task.sut).run(script, task.seed, interface, slot, task.trace_id)
        except UntimelyError as e:  # the user's input (a variant, world or adapter that cannot be used)
            return e
        except Exception:  # noqa: BLE001 - any other failure is this run's crash
            return crashed(task, traceback.format_exc().strip(), time.perf_counter() - start)


def script_label(script_id: int) -> str:
    """How messages about a stored script name it (its scripts.script_id)."""
    return f"script {script_id}"


def crashed(task: Task, error: str, wall_s: float = 0.0) -> Trace:
    return Trace(sut=task.sut, seed=task.seed, outcome="crashed", error=error, wall_s=wall_s)
