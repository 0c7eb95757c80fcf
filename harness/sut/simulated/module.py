"""A GenoM-flavoured module: a control task serving requests in order, and activities.

The control task takes one request at a time, CONTROL_LATENCY_S after the previous one; a
deadlocked module's control task stops for good, and with it every reply of the module.
An activity (exec or init request) is a kernel process: a start phase, then (exec only) the
intermediate reply, then its body, whose return value is the final reply. An interruption
ends it at once with the code it was given, after the module's clean-up for that service.
"""
from __future__ import annotations

from collections import deque
from typing import Callable, Generator

from harness.sut.simulated.kernel import Environment, Interrupt

CONTROL_LATENCY_S = 0.001
DEFAULT_START_S = 0.1
FROZEN = None  # interruption cause of a deadlock: the activity ends without any reply

Reply = Callable[[str, "str | None"], None]  # (kind, code) of one request


class Activity:
    def __init__(self, module: "Module", rqst_id: int, service: str, kind: str, args: dict, reply: Reply):
        self.module, self.rqst_id, self.service, self.kind = module, rqst_id, service, kind
        self.args, self.reply = args, reply
        self.phase = "starting"  # -> running -> ended
        self.process = None

    @property
    def qualified(self) -> str:
        return f"{self.module.name}.{self.service}"

    def interrupt(self, code: str | None) -> None:
        """End the activity with final reply `code` (FROZEN: no reply); a no-op once it is ending."""
        if self.phase == "ended":
            return
        self.phase = "ended"
        self.module.activities.remove(self)
        self.process.interrupt(code)

    def __repr__(self) -> str:
        return f"<Activity {self.qualified} #{self.rqst_id} {self.phase}>"


class Module:
    """Generic module; subclasses give `name`, `settings` defaults, `bodies` and `start_s`. A
    service without a body of its own can be given a timed one (`add_timed`)."""

    name = "module"
    start_s: dict[str, float] = {}  # start phase of each service

    def __init__(self, env: Environment, name: str | None = None):
        self.env = env
        self.name = name or self.name
        self.start_s = dict(type(self).start_s)
        self.activities: list[Activity] = []
        self.initialised = False
        self.deadlocked = False
        self.settings: dict = {}
        self.bodies: dict[str, Callable[[Activity], Generator]] = {}
        self._queue: deque[Callable[[], None]] = deque()

    # -- control task ------------------------------------------------------------------------
    def enqueue(self, handle: Callable[[], None]) -> None:
        self._queue.append(handle)
        if len(self._queue) == 1:
            self.env.call_at(self.env.now + CONTROL_LATENCY_S, self._serve)

    def _serve(self) -> None:
        if self.deadlocked:
            return
        self._queue[0]()
        self._queue.popleft()
        if self._queue and not self.deadlocked:
            self.env.call_at(self.env.now + CONTROL_LATENCY_S, self._serve)

    def freeze(self) -> None:
        """Deadlock: the control task stops and every activity falls silent."""
        self.deadlocked = True
        for activity in list(self.activities):
            activity.interrupt(FROZEN)

    def configure(self, values: dict) -> None:
        self.settings.update(values)

    # -- activities --------------------------------------------------------------------------
    @property
    def initialising(self) -> bool:
        return any(a.kind == "init" for a in self.activities)

    def running(self, *services: str) -> list[Activity]:
        """Exec activities (of the given services, or all), oldest first."""
        return [a for a in self.activities if a.kind == "exec" and (not services or a.service in services)]

    def start(self, rqst_id: int, service: str, kind: str, args: dict, reply: Reply) -> Activity:
        activity = Activity(self, rqst_id, service, kind, args, reply)
        self.activities.append(activity)
        activity.process = self.env.process(self._lifecycle(activity), f"{self.name}.{service}#{rqst_id}")
        return activity

    def _lifecycle(self, activity: Activity):
        try:
            yield self.env.timeout(self.start_s.get(activity.service, DEFAULT_START_S))
            activity.phase = "running"
            if activity.kind == "exec":
                activity.reply("intermediate", None)
            code = yield from self.bodies[activity.service](activity)
            activity.phase = "ended"
            self.activities.remove(activity)
        except Interrupt as stop:
            code = stop.cause
        if code is FROZEN:
            return
        self.ended(activity)
        activity.reply("final", code)

    def ended(self, activity: Activity) -> None:
        """Clean-up after any non-frozen end of an activity (normal or interrupted)."""

    def add_timed(self, service: str, start_s: float, run_s: float | None) -> None:
        """A service with no codel: a start phase, then a wait of `run_s` (None: until interrupted)
        that ends ok; an init activity's end initialises the module."""
        self.start_s.setdefault(service, start_s)
        self.bodies.setdefault(service, lambda activity: self._wait(activity, run_s))

    def _wait(self, activity: Activity, run_s: float | None):
        yield self.env.event() if run_s is None else self.env.timeout(run_s)
        if activity.kind == "init":
            self.initialised = True
        return "ok"

    def __repr__(self) -> str:
        state = "deadlocked" if self.deadlocked else "initialised" if self.initialised else "uninitialised"
        listed = ", ".join(f"{a.service}#{a.rqst_id} {a.phase}" for a in self.activities)
        return f"<Module {self.name} {state} [{listed}]>"
