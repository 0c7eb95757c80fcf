"""The simulated Dala functional layer: the executive's only door into the simulation.

A request reaches its module's control task, which checks it (bad_params, PEX, PRE, free slot;
see variants.py), applies the interruptions it causes (AIB, EXC, the variant's quirks), then
starts it. Replies go back through the `reply` callable given with each request.
"""
from __future__ import annotations

from pathlib import Path
from typing import Callable

from harness.errors import UntimelyError
from harness.interface import Interface, Service
from harness.sut import rules
from harness.sut.kernel import Environment
from harness.sut.module import CONTROL_LATENCY_S, Activity, Module
from harness.sut.modules import Posters, build_modules
from harness.sut.variants import (DEADLOCK_ON_DOMINATED_START, DEADLOCK_ON_EXCLUDED_START, INIT_INTERRUPTS,
                                  PEX_LEAK_DURING_INIT, variant_named)
from harness.sut.world import World, load_world

ACTIVITY_SLOTS = 3  # exec activities a module runs at once


def parse_args(service: Service, raw: dict[str, str]) -> dict | None:
    """Typed argument values, or None when any is missing, unknown or outside its domain."""
    if set(raw) != set(service.args):
        return None
    values = {}
    for name, text in raw.items():
        spec = service.args[name]
        if spec.type == "str":
            if text not in spec.choices:
                return None
            values[name] = text
            continue
        try:
            value = float(text)
        except ValueError:
            return None
        if not spec.min <= value <= spec.max:  # also refuses nan
            return None
        values[name] = value
    return values


class FunctionalLayer:
    def __init__(self, env: Environment, variant: str, interface: Interface, world_file: Path):
        self.env, self.interface, self.variant_name = env, interface, variant
        self.variant = variant_named(variant)
        self.world = World(load_world(world_file), env)
        self.world_events = self.world.events
        self.posters = Posters(robot=self.world.pose)
        self.modules = build_modules(env, self.world, self.posters)
        self.succeeded: set[str] = set()  # services that have ended ok at least once (for PRE)
        self._check_implements(interface)

    def _check_implements(self, interface: Interface) -> None:
        for service in interface.services.values():
            module = self.modules.get(service.module)
            if module is None or (service.kind != "control" and service.name not in module.bodies):
                raise UntimelyError(f"the interface {interface.path} declares {service.qualified} "
                                    f"({service.kind}), which the simulated Dala layer does not implement; "
                                    f"use an interface with only modules {', '.join(self.modules)}")

    def has(self, protection: str) -> bool:
        return protection in self.variant.protections

    def receive(self, rqst_id: int, service: str, args: dict[str, str], reply: Callable) -> None:
        spec = self.interface.services.get(service)
        if spec is None:
            raise UntimelyError(f"request {rqst_id} names {service!r}, which the interface "
                                f"{self.interface.path} does not declare")

        def answer(kind: str, code: str | None) -> None:
            if kind == "final" and code == "ok":
                self.succeeded.add(service)
            reply(rqst_id, kind, code)
        module = self.modules[spec.module]

        def take() -> None:
            reply(rqst_id, "request", None)  # the internal instant the layer decides on it
            self._handle(module, rqst_id, spec, args, answer)
        module.enqueue(take)

    def _handle(self, module: Module, rqst_id: int, service: Service, raw: dict, answer) -> None:
        values = parse_args(service, raw)
        rejection = "bad_params" if values is None else self._rejection(module, service)
        if rejection:
            answer("final", rejection)
        elif service.kind == "control":
            module.configure(values)
            answer("final", "ok")
        else:
            self._interrupt_for(module, service)
            if not module.deadlocked:
                module.start(rqst_id, service.name, service.kind, values, answer)

    def _rejection(self, module: Module, service: Service) -> str | None:
        if service.kind != "exec":
            return None
        leak = PEX_LEAK_DURING_INIT in self.variant.defects and module.initialising
        if self.has("PEX") and not module.initialised and not leak:
            return "wait_init"
        if self.has("PRE") and not rules.REQUIREMENTS.get(service.qualified, set()) <= self.succeeded:
            return "disallowed"
        if len(module.running()) >= ACTIVITY_SLOTS:
            return "too_many_activities"
        return None

    def _victims(self, module: Module, service: Service) -> list[tuple[Activity, str]]:
        """The running activities an accepted request ends, each with its final reply."""
        if service.kind == "init":
            return [(a, "interrupted") for a in module.running()] if INIT_INTERRUPTS in self.variant.defects else []
        request = service.qualified
        dominated = [a for a in module.running() if rules.dominates(request, a.qualified)]
        if self.has("AIB"):
            victims = [(a, "interrupted") for a in dominated]
        else:  # a Stop still stops, but nothing says it interrupted anything
            victims = [(a, "ok") for a in dominated if rules.is_stop(request)]
        if self.has("EXC"):
            excluded = rules.excluded_by(request)
            victims += [(a, "interrupted_excl") for m in self.modules.values() for a in m.running()
                        if a.qualified in excluded]
        return victims

    def _interrupt_for(self, module: Module, service: Service) -> None:
        """Interrupt what an accepted request ends; a defective variant may deadlock instead."""
        deadlocking = {"interrupted": DEADLOCK_ON_DOMINATED_START, "interrupted_excl": DEADLOCK_ON_EXCLUDED_START}
        for activity, code in self._victims(module, service):
            if activity.phase == "starting" and deadlocking.get(code) in self.variant.defects:
                activity.module.freeze()
            else:
                activity.interrupt(code)

    def ping(self, answer: Callable[[], None]) -> None:
        """Liveness probe: answered one control latency later, unless a module is deadlocked."""
        def respond() -> None:
            if not any(m.deadlocked for m in self.modules.values()):
                answer()
        self.env.call_at(self.env.now + CONTROL_LATENCY_S, respond)

    def __repr__(self) -> str:
        modules = " ".join(repr(m) for m in self.modules.values())
        return f"<FunctionalLayer {self.variant_name} t={self.env.now:.3f} {modules}>"
