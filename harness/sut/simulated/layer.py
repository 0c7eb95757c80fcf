"""The simulated functional layer: the executive's only door into the simulation.

What the layer is made of comes from its mission folder: the modules from the behaviour module
that layer.toml names (or timed modules built from the interface and [timing]), what it enforces
from layer.toml's protections, defects and variants (harness/target/layer_description.py).

A request reaches its module's control task, which checks it (the variant's argument checks, then
its rejecting protections in their declared order, then a free activity slot), applies the
interruptions it causes (the interrupting protections, the layer's stop service, the variant's
defects), then starts it. Replies go back through the `reply` callable given with each request.
"""
from __future__ import annotations

import json
from pathlib import Path
from typing import Callable

from harness.errors import UntimelyError
from harness.target.domains import carried, number, violation
from harness.target.interface import Interface, Service
from harness.target.layer_description import Protection
from harness.target.mission import load_layer
from harness.sut.simulated.kernel import Environment
from harness.sut.simulated.module import CONTROL_LATENCY_S, Activity, Module


def read_args(service: Service, raw: dict[str, str]) -> dict:
    """The argument values a module gets, unchecked: numbers as read (nan and infinities too), a
    word that is no number as 0 (C's atof), a missing number as 0 and a missing text as ""."""
    values = {}
    for name, arg in service.args.items():
        word = raw.get(name)
        if arg.type == "str":
            values[name] = "" if word is None else carried(arg, word)
        else:
            values[name] = 0.0 if word is None or number(word) is None else number(word)
    return values


def build_modules(env: Environment, description, interface: Interface, world_file: Path) -> tuple[dict, list]:
    """The modules by name and the world's event list (virtual damage; empty without a world)."""
    if description.behaviour:
        return description.behaviour_module().build(env, world_file)
    return {m: Module(env, m) for m in interface.modules}, []


class FunctionalLayer:
    def __init__(self, env: Environment, variant: str, interface: Interface, world_file: Path):
        self.env, self.interface, self.variant_name = env, interface, variant
        self.description = load_layer(Path(world_file).parent)  # the world's folder, even if it has none
        self.description.check(interface)
        self.variant = self.description.variant(variant)
        self.modules, self.world_events = build_modules(env, self.description, interface, world_file)
        self.succeeded: set[str] = set()  # services that have ended ok at least once
        self._check_implements(interface)

    def _check_implements(self, interface: Interface) -> None:
        for service in interface.services.values():
            module = self.modules.get(service.module)
            timing = self.description.timing_of(service.qualified)
            if module is not None and timing and service.kind != "control":
                module.add_timed(service.name, timing.start_s, timing.run_s)
            if module is None or (service.kind != "control" and service.name not in module.bodies):
                raise UntimelyError(f"the interface {interface.path} declares {service.qualified} "
                                    f"({service.kind}), which the simulated layer does not implement; "
                                    f"use an interface with only modules {', '.join(self.modules)}, or give "
                                    f"the service a [timing] entry in {self.description.path}")

    def _is_stop(self, qualified: str) -> bool:
        return qualified.split(".", 1)[1] == self.description.stop

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
        rejection = self._bad_args(service, raw) or self._rejection(module, service)
        if rejection:
            answer("final", rejection)
            return
        self._note_unchecked(rqst_id, service, raw)
        values = read_args(service, raw)
        if service.kind == "control":
            module.configure(values)
            answer("final", "ok")
        else:
            self._interrupt_for(module, service)
            if not module.deadlocked:
                module.start(rqst_id, service.name, service.kind, values, answer)

    def _bad_args(self, service: Service, raw: dict) -> str | None:
        """The reply of the variant's first argument check the request fails, if any."""
        for p in self.variant.protections:
            if p.kind == "checks_args":
                if any(violation(arg, raw.get(name)) in p.checks for name, arg in service.args.items()):
                    return p.reply
            elif p.kind == "narrows_while" and self._running(p.services.get(service.qualified, frozenset())):
                narrowed = self.description.narrowed(p, service.args)
                if any(violation(service.args[n], raw.get(n), domain) for n, domain in narrowed.items()):
                    return p.reply
        return None

    def _note_unchecked(self, rqst_id: int, service: Service, raw: dict) -> None:
        """Ground truth: a value outside its interface domain that the layer let through."""
        for name, arg in service.args.items():
            broken = violation(arg, raw.get(name))
            if broken:
                self.world_events.append((self.env.now, "unchecked_value", json.dumps(
                    {"rqst_id": rqst_id, "service": service.qualified, "argument": name,
                     "value": raw.get(name), "violation": broken})))

    def _running(self, services: frozenset[str]) -> bool:
        return any(a.qualified in services for m in self.modules.values() for a in m.running())

    def _rejects(self, protection: Protection, module: Module, request: str) -> bool:
        if protection.kind == "requires_init":
            leak = self.variant.defect("leak_during_init", protection.name) and module.initialising
            return not module.initialised and not leak
        if protection.kind == "requires":
            return not protection.services.get(request, frozenset()) <= self.succeeded
        if protection.kind == "rejects_while":
            return self._running(protection.services.get(request, frozenset()))
        return False

    def _rejection(self, module: Module, service: Service) -> str | None:
        if service.kind != "exec":
            return None
        for protection in self.variant.protections:
            if self._rejects(protection, module, service.qualified):
                return protection.reply
        if len(module.running()) >= self.description.slots:
            return self.description.no_slot
        return None

    def _victims(self, module: Module, service: Service) -> list[tuple[Activity, str, str]]:
        """The running activities an accepted request ends, each with its final reply and the
        protection or defect that ends it."""
        if service.kind == "init":
            quirk = self.variant.defect("interrupts_on_init")
            return [(a, quirk.reply, quirk.name) for a in module.running()] if quirk else []
        request = service.qualified
        interrupting = [p for p in self.variant.protections if p.kind in ("interrupts", "excludes")]
        victims = []
        if self._is_stop(request) and not any(p.stop for p in interrupting):
            # a stop still stops, but nothing says it interrupted anything
            victims = [(a, "ok", "") for a in module.running() if not self._is_stop(a.qualified)]
        for p in interrupting:
            victims += [(a, p.reply, p.name) for m in self.modules.values() for a in m.running()
                        if request in p.services.get(a.qualified, ()) or
                        (p.stop and m is module and self._is_stop(request) and not self._is_stop(a.qualified))]
        return victims

    def _interrupt_for(self, module: Module, service: Service) -> None:
        """Interrupt what an accepted request ends; a defective variant may deadlock instead."""
        for activity, code, cause in self._victims(module, service):
            if activity.phase == "starting" and self.variant.defect("deadlock_on_start", cause):
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
