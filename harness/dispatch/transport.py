"""How a run reaches its SUT: every kind of SUT is a `Transport`, whose `run` plays one script and
returns its trace. The simulated layer runs in this process in virtual time (`Simulated`); an
adapter speaking untimely/1 runs in wall-clock time (`ExternalTransport`), started for the run on stdio
(`--sut NAME=cmd:COMMAND`; the ROS 1 and ROS 2 launchers are such commands) or reached over TCP
(`NAME=tcp://HOST:PORT`), the channel that harness.sut.external.channel opens for its
definition.

A SUT's name is offered to the kinds of REGISTRY in order; the first that takes it makes its
transport. A new kind of SUT is one class with `run` and one entry there (a run's Setup, made by
`setup`, takes the registry as it stands then, and carries it to the worker processes).
"""
from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Callable, Protocol

from harness.dispatch.description import Setup
from harness.target.suts import ExternalSut
from harness.sut.external.runner import run_external
from harness.target.interface import Interface
from harness.target.script import Script
from harness.trace import Trace


class Transport(Protocol):
    name: str

    def run(self, script: Script, seed: int, interface: Interface, slot: int = 0, trace_id: int = 0) -> Trace:
        """One run on a slot (an adapter may pick its ports from it) making trace `trace_id`; a
        SUT that misbehaves gives a hung or crashed trace, one that cannot be used raises
        UntimelyError."""


@dataclass(frozen=True)
class Simulated:
    """A variant of the simulated layer; `runner` has run_script's signature (tests inject others)."""
    name: str
    runner: Callable
    world_file: Path
    max_delay: float

    def run(self, script: Script, seed: int, interface: Interface, slot: int = 0, trace_id: int = 0) -> Trace:
        return self.runner(script, self.name, seed, interface, self.world_file, self.max_delay)


@dataclass(frozen=True)
class ExternalTransport:
    """An external SUT over untimely/1, on the channel its definition names (stdio or TCP)."""
    sut: ExternalSut

    @property
    def name(self) -> str:
        return self.sut.name

    def run(self, script: Script, seed: int, interface: Interface, slot: int = 0, trace_id: int = 0) -> Trace:
        return run_external(script, self.sut, seed, interface, slot, trace_id)


def _external(name: str, setup: Setup) -> Transport | None:
    return ExternalTransport(setup.external[name]) if name in setup.external else None


def _simulated(name: str, setup: Setup) -> Transport:
    return Simulated(name, setup.runner, setup.world_file, setup.max_delay)


# The kinds of SUT, tried in order: the first whose maker returns a transport for a name runs it.
REGISTRY: list[Callable[[str, Setup], Transport | None]] = [_external, _simulated]


def setup(runner: Callable, interface_file: Path, world_file: Path, max_delay: float,
          external: dict[str, ExternalSut] | None = None, watchdog_s: float | None = None) -> Setup:
    """What every run of a campaign (or a shrink's, or an ad-hoc run) shares, with the kinds of SUT
    of REGISTRY; `runner` has harness.sut.executive.run_script's signature (tests give others)."""
    return Setup(runner, interface_file, world_file, max_delay, external or {}, watchdog_s, kinds=tuple(REGISTRY))
