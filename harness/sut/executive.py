"""The mission executive: plays a validated script against a functional layer in virtual time.

`send` is non-blocking, and so is `cancel`: a request of the cancel service of the goal it names,
whose argument `goal` is that goal's request id (docs/reference/mission-language.md); `wait` blocks until the awaited final replies are observed (or its
watchdog expires: the wait is abandoned and noted, the script goes on), then the executive
takes REACTION_S to react. An out-of-band liveness
probe pings the layer every PROBE_PERIOD; a layer that does not answer within PROBE_TIMEOUT has
stopped answering and the trace ends `hung`. An exception inside the layer ends it `crashed`.

Every message crosses the interface with a seeded random delay in [0, max_delay]: a request is
observed when the executive sends it and reaches the layer later; a reply leaves the layer and is
observed later. The observed timeline goes to `events`, the layer's own to `internal_events`; a
layer that replies `taken` when it takes a request (an external SUT may) has those replies
observed into `taken_events`.
"""
from __future__ import annotations

import json
import random
import time
import traceback
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Callable

from harness.errors import InternalSignal
from harness.target.interface import Interface
from harness.target.script import CANCEL_GOAL_ARG, SIMULATED_NO_CANCEL, Script, Step, cancel_service, refuse_cancels
from harness.sut.simulated.kernel import Environment, Event
from harness.trace import Trace

WAIT_TIMEOUT_S = 120.0  # watchdog of a `wait` without timeout=
DRAIN_S = 10.0  # how long outstanding replies are awaited after the last step
# An executive takes time to react to the replies it awaited (OpenPRS runs in cycles of tens of
# ms); without it, a request sent after a `wait` would be observed at the reply's very instant.
REACTION_S = 0.02
PROBE_PERIOD_S = 1.0
PROBE_TIMEOUT_S = 0.5


@dataclass(frozen=True)
class Probe:
    """The liveness probe, in mission seconds: a ping every `period_s`, answered within `timeout_s`."""
    period_s: float = PROBE_PERIOD_S
    timeout_s: float = PROBE_TIMEOUT_S


class LayerMisbehaved(InternalSignal):
    """The layer broke the interface protocol (unknown code, second final reply, unknown request)."""


@dataclass
class SentRequest:
    """A request the executive sent (a send's or a cancel's), followed until its final reply is observed."""
    rqst_id: int
    step: Step
    args: str  # as JSON text
    taken: bool = False  # the layer's control task has taken it
    said_taken: bool = False  # the layer has replied `taken`
    final: str | None = None
    observed: Event | None = None  # succeeds when the final reply is observed


@dataclass
class _Log:
    rows: list[tuple] = field(default_factory=list)

    def add(self, t, kind, request: SentRequest, reply=None):
        """One event row; only a request carries the arguments."""
        module, service = request.step.service.split(".")
        args = request.args if kind == "request" else None
        self.rows.append((len(self.rows) + 1, t, kind, request.rqst_id, module, service, args, reply))


class Executive:
    def __init__(self, env: Environment, layer, interface: Interface, rng: random.Random,
                 max_delay: float, probe: Probe = Probe()):
        self.env, self.layer, self.interface = env, layer, interface
        self.rng, self.max_delay = rng, max_delay
        self.probe_period, self.probe_timeout = probe.period_s, probe.timeout_s
        self.requests: dict[int, SentRequest] = {}
        self.handles: dict[str, SentRequest] = {}
        self.observed, self.internal = _Log(), _Log()
        self.notes: list[tuple[float, str, str]] = []
        self.done = env.event()  # value: the outcome

    def _delay(self) -> float:
        return self.rng.uniform(0.0, self.max_delay)

    def send(self, step: Step) -> None:
        """A send's request, or a cancel's: of the cancel service of the goal it names, with its id."""
        args = dict(step.args)
        if step.op == "cancel":
            goal = self.handles[step.cancelled]
            step, args = replace(step, service=cancel_service(goal.step.service)), {CANCEL_GOAL_ARG: goal.rqst_id}
        typed = json.dumps(self.interface.services[step.service].typed(args))
        request = SentRequest(len(self.requests) + 1, step, typed, observed=self.env.event())
        self.requests[request.rqst_id] = request
        if step.handle:
            self.handles[step.handle] = request
        self.observed.add(self.env.now, "request", request)
        self.env.call_at(self.env.now + self._delay(),
                         lambda: self.layer.receive(request.rqst_id, step.service, args, self.on_reply))

    def on_reply(self, rqst_id: int, kind: str, code: str | None) -> None:
        """The layer's messages: `request` when its control task takes the request (the internal
        instant the layer decides on it, not observed), then `intermediate` and `final` replies;
        a layer may also reply `taken` at that instant, an observed reply without its own row of
        ground truth (the `request` one is it)."""
        request = self.requests.get(rqst_id)
        if request is None:
            raise LayerMisbehaved(f"the layer replied to request {rqst_id}, which was never sent")
        if kind == "request":
            if request.taken:
                raise LayerMisbehaved(f"the layer took request {rqst_id} ({request.step.service}) twice")
            request.taken = True
            self.internal.add(self.env.now, "request", request)
            return
        if request.final is not None:
            raise LayerMisbehaved(f"the layer sent a {kind} reply {code!r} to request {rqst_id} "
                                  f"({request.step.service}) after its final reply {request.final!r}")
        if kind == "final":
            if code not in self.interface.replies:
                raise LayerMisbehaved(f"the layer replied {code!r} to request {rqst_id} "
                                      f"({request.step.service}); the interface catalogue has no such code")
            request.final = code
        if kind == "taken":
            if request.said_taken:
                raise LayerMisbehaved(f"the layer replied taken to request {rqst_id} ({request.step.service}) twice")
            request.said_taken = True
        else:
            self.internal.add(self.env.now, kind, request, code)

        def observe():
            self.observed.add(self.env.now, kind, request, code)
            if kind == "final":
                request.observed.succeed()
        self.env.call_at(self.env.now + self._delay(), observe)

    def _await(self, requests: list[SentRequest], timeout: float, what: str):
        deadline = self.env.now + timeout
        for request in requests:
            while not request.observed.triggered:
                if self.env.now >= deadline:
                    self.notes.append((self.env.now, "wait_timeout", json.dumps({"wait": what})))
                    return
                watchdog = self.env.timeout(deadline - self.env.now)
                yield self.env.any_of(request.observed, watchdog)

    def play(self, script: Script):
        for step in script.steps:
            if step.op in ("send", "cancel"):
                self.send(step)
            elif step.op == "sleep":
                yield self.env.timeout(step.seconds)
            else:
                awaited = (list(self.requests.values()) if step.handle == "all"
                           else [self.handles[step.handle]])
                label = f"line {step.line}: wait {step.handle}"
                yield from self._await(awaited, step.seconds or WAIT_TIMEOUT_S, label)
                yield self.env.timeout(REACTION_S)
        yield from self._await(list(self.requests.values()), DRAIN_S, "drain at end of script")
        if not self.done.triggered:
            self.done.succeed("completed")

    def probe(self):
        while True:
            yield self.env.timeout(self.probe_period)
            answered = self.env.event()
            self.layer.ping(lambda: answered.triggered or answered.succeed())
            # counted from when the ping really went out: a kernel late behind a flood of
            # messages must not blame the layer for its own delay
            yield self.env.any_of(answered, self.env.timeout(self.probe_timeout + self.env.lag()))
            if not answered.triggered:
                self.notes.append((self.env.now, "probe_unanswered", json.dumps({})))
                if not self.done.triggered:
                    self.done.succeed("hung")
                return


@dataclass(frozen=True)
class Runner:
    """Runs one script on one variant; never raises for a hung or crashing layer. The layers are
    what `layer_factory(env, sut, interface, world_file)` builds: by default the simulated layer
    that the world file's mission folder describes (layer.toml), a fake one in the executive's and
    the campaign's tests. The worker pool calls (and pickles) a runner: it is a value, not a closure."""
    layer_factory: Callable | None = None

    def __call__(self, script: Script, sut: str, seed: int, interface: Interface, world_file: Path | None,
                 max_delay: float = 0.003) -> Trace:
        layer_factory = self.layer_factory
        if layer_factory is None:
            refuse_cancels(script, SIMULATED_NO_CANCEL)
            from harness.sut.simulated.layer import FunctionalLayer as layer_factory
        wall = time.perf_counter()
        env = Environment()
        trace = Trace(sut=sut, seed=seed)
        layer = layer_factory(env, sut, interface, world_file)  # a bad variant or world is the user's error
        executive = Executive(env, layer, interface, random.Random(seed), max_delay)
        try:
            env.process(executive.play(script), "executive")
            env.process(executive.probe(), "liveness probe")
            env.run(until=executive.done)
            trace.outcome = executive.done.value
        except Exception as e:  # noqa: BLE001 - any failure inside the layer is a crashed trace
            trace.outcome = "crashed"
            trace.error = "".join(traceback.format_exception_only(e)).strip()
        return trace_of(executive, env, trace, wall, executive.internal.rows, layer.world_events)


run_script = Runner()  # on the simulated layer


def trace_of(executive: Executive, env: Environment, trace: Trace, wall_start: float,
             internal: list[tuple], world: list[tuple]) -> Trace:
    """A finished run's timelines and clocks, into its trace: the observed events, the layer's
    internal ones, its virtual damage with the executive's notes."""
    trace.events = [row for row in executive.observed.rows if row[2] != "taken"]
    trace.taken_events = [(seq, t, rqst_id) for seq, t, kind, rqst_id, *_ in executive.observed.rows
                          if kind == "taken"]
    trace.internal_events = internal
    trace.world_events = sorted(list(world) + executive.notes)
    trace.sim_s, trace.wall_s = env.now, time.perf_counter() - wall_start
    return trace
