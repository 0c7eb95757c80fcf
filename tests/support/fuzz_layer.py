"""A seeded generator of random traces of the manipulator (missions/manipulator) for the interval
fuzz test: a small functional layer played in its own time (the internal timeline) and the client's
delayed view of it (the observed one), as the executive records them.

The layer takes each request when it reaches it (sent + a delay in [0, MAX_DELAY]) and decides on
it at that instant from its own state, enforcing the protections its variant has: PEX (wait_init
before the module's Init ended ok), VAL and SLOW (bad_params), SPEED (unsafe_speed), BLUR (blurred,
and a Sprint cuts a Capture short with blur_interrupted), GRASP (busy), AIB (a dominating request of
the module interrupts its activity) and EXC (the latest of a Move and a Reach preempts the other).
Variant `quirky` also interrupts a module's activities on its Init (GenoM's undocumented
behaviour: an AIB FP, and a cause of interruption that is no y of the property); `telling` replies
`taken` when it takes a request, before deciding on it, and its replies come down one channel in the
order it wrote them (protocol untimely/1); a trace `hangs` when one module deadlocks at a random instant (it takes no request and
ends no activity after it, the others go on; the trace ends when the liveness probe gives up). A reply is observed
a delay after it leaves the layer (independently of the others, as in the simulator, except on
`telling`'s one channel); both timelines end at the same instant, so a reply in flight
then is lost. Everything is drawn from random.Random(seed).
"""
from __future__ import annotations

import json
import random
from dataclasses import dataclass, field

from harness.trace import Trace

MAX_DELAY = 0.003  # each message's delay, as the executive's default --max-delay
CONTROL_S = 0.001  # a control request or a rejection is answered after this
DRAIN_S = 1.0  # outstanding replies are awaited this long after the last request
PROBE_S = 0.3  # a hung layer's trace ends this long after it stopped
VARIANTS = ("strict", "lax", "half", "quirky", "telling")
# Variant -> the protections it has.
PROTECTIONS = {"strict": {"PEX", "VAL", "SLOW", "SPEED", "BLUR", "GRASP", "AIB", "EXC"},
               "lax": set(), "half": {"PEX", "SPEED", "GRASP", "AIB"},
               "quirky": {"PEX", "VAL", "SLOW", "SPEED", "BLUR", "GRASP", "AIB", "EXC"},
               "telling": {"VAL", "BLUR", "EXC", "AIB"}}
# Service -> possible arguments (None: none), drawn in and out of the interface's domains.
ARGS = {"base.Move": [{"speed": 0.2}, {"speed": 0.5}, {"speed": 1.5}],
        "base.Sprint": [{"speed": 1.5}, {"speed": 3.0}],
        "arm.Reach": [{"object": "cup"}, {"object": "anvil"}],
        "camera.Capture": [{"label": "photo_1"}, {"label": "Bad Label"}, {}],
        "camera.SetExposure": [{"ms": 10.0}, {"ms": 500.0}]}
SERVICES = ["base.Init", "base.Move", "base.Move", "base.Sprint", "base.Sprint", "base.Stop", "arm.Init",
            "arm.Deploy", "arm.Reach", "arm.Reach", "arm.Stop", "gripper.Init", "gripper.Open", "gripper.Close",
            "gripper.Close", "gripper.Stop", "camera.Init", "camera.SetExposure", "camera.Capture",
            "camera.Capture", "camera.Track", "camera.Stop"]
UNTIL_STOPPED = {"arm.Deploy", "camera.Track"}
# Running service -> (requests that end it, code, protection; None: always).
ENDS = {"base.Move": [({"base.Move", "base.Sprint", "base.Stop"}, "interrupted", "AIB"),
                      ({"arm.Reach"}, "preempted", "EXC")],
        "base.Sprint": [({"base.Move", "base.Sprint", "base.Stop"}, "interrupted", "AIB")],
        "arm.Reach": [({"base.Move"}, "preempted", "EXC"), ({"arm.Stop"}, "interrupted", None)],
        "arm.Deploy": [({"arm.Stop"}, "interrupted", None)],
        "gripper.Open": [({"gripper.Stop"}, "interrupted", None)],
        "gripper.Close": [({"gripper.Stop"}, "interrupted", None)],
        "camera.Capture": [({"base.Sprint"}, "blur_interrupted", "BLUR")],
        "camera.Track": [({"camera.Track", "camera.Stop"}, "interrupted", "AIB")]}
# Gaps between consecutive requests: many within epsilon of each other, some at the same instant.
GAPS = (0.0, 0.0, 0.001, 0.002, 0.004, 0.006, 0.009, 0.02, 0.05, 0.1, 0.2, 0.4)


@dataclass
class Activity:
    rqst_id: int
    service: str
    end: float  # when it ends by itself (inf: until stopped)


@dataclass
class Layer:
    """The layer's state at its own instants, and the replies it emitted: (emitted, rqst_id, code)."""
    protections: set[str]
    quirky: bool
    running: list[Activity] = field(default_factory=list)
    initialised: dict[str, float] = field(default_factory=dict)  # module -> when its Init ended ok
    replies: list[tuple[float, int, str]] = field(default_factory=list)
    dead: tuple[str, float] = ("", float("inf"))  # a module that deadlocks, and when

    def alive(self, service: str, u: float) -> bool:
        return not (service.startswith(self.dead[0] + ".") and u >= self.dead[1])

    def end_until(self, u: float) -> None:
        """Activities that end by themselves before u reply ok (an Init initialises its module)."""
        for a in sorted((a for a in self.running if a.end <= u and self.alive(a.service, a.end)),
                        key=lambda a: a.end):
            self.running.remove(a)
            self.replies.append((a.end, a.rqst_id, "ok"))
            if a.service.endswith(".Init"):
                self.initialised.setdefault(a.service.split(".")[0], a.end)

    def runs(self, *services: str) -> bool:
        return any(a.service in services for a in self.running)

    def refusal(self, service: str, args: dict) -> str | None:
        """The rejection code of the first protection that refuses the request now, if any."""
        module, on = service.split(".")[0], self.protections
        legal = _legal(service, args)
        checks = [("PEX", not service.endswith(".Init") and module not in self.initialised, "wait_init"),
                  ("VAL", not legal, "bad_params"),
                  ("SLOW", service == "base.Move" and args.get("speed", 0) > 0.3 and self.runs("arm.Deploy"),
                   "bad_params"),
                  ("SPEED", service == "base.Sprint" and self.runs("arm.Deploy"), "unsafe_speed"),
                  ("BLUR", service == "camera.Capture" and self.runs("base.Sprint"), "blurred"),
                  ("GRASP", service == "arm.Reach" and self.runs("gripper.Close"), "busy"),
                  ("GRASP", service == "gripper.Close" and self.runs("arm.Reach"), "busy")]
        return next((code for name, applies, code in checks if name in on and applies), None)

    def take(self, u: float, rqst_id: int, service: str, args: dict, duration: float, tells: bool) -> None:
        self.end_until(u)
        if tells:
            self.replies.append((u, rqst_id, "taken"))
        if (code := self.refusal(service, args)) is not None:
            self.replies.append((u + CONTROL_S, rqst_id, code))
            return
        if service == "camera.SetExposure":
            self.replies.append((u + CONTROL_S, rqst_id, "ok"))
            return
        module = service.split(".")[0]
        for a in list(self.running):
            ended = [code for by, code, protection in ENDS.get(a.service, [])
                     if service in by and (protection is None or protection in self.protections)]
            if self.quirky and service.endswith(".Init") and a.service.startswith(module + "."):
                ended.append("interrupted")
            if ended and self.alive(a.service, u):
                self.running.remove(a)
                self.replies.append((u, a.rqst_id, ended[0]))
        self.running.append(Activity(rqst_id, service, float("inf") if service in UNTIL_STOPPED else u + duration))


def _legal(service: str, args: dict) -> bool:
    """The interface's domains (missions/manipulator/interface.toml) for the arguments drawn here."""
    value = next(iter(args.values()), None)
    return {"base.Move": lambda: 0.05 <= value <= 1.0, "base.Sprint": lambda: 1.0 <= value <= 2.5,
            "arm.Reach": lambda: value in ("cup", "bottle", "box"),
            "camera.Capture": lambda: value is None or value.replace("_", "a").isalnum() and value.islower(),
            "camera.SetExposure": lambda: 1.0 <= value <= 100.0}.get(service, lambda: True)()


def random_trace(seed: int) -> Trace:
    """One random script played on one random variant: both timelines, taken replies if it tells."""
    rng = random.Random(seed)
    variant = rng.choice(VARIANTS)
    layer = Layer(PROTECTIONS[variant], variant == "quirky")
    sent, t = [], 0.0
    for rqst_id in range(1, rng.randint(6, 24) + 1):
        t = round(t + rng.choice(GAPS), 6)
        service = rng.choice(SERVICES) if rqst_id > 2 or rng.random() < 0.3 else f"{rng.choice(['base', 'arm'])}.Init"
        args = rng.choice(ARGS.get(service, [{}]))
        sent.append((t, rqst_id, service, args, t + rng.uniform(0, MAX_DELAY), rng.choice((0.01, 0.05, 0.3))))
    stop = rng.uniform(0, t + 0.3) if rng.random() < 0.25 else None  # a module deadlocks then
    if stop is not None:
        layer.dead = (rng.choice(["base", "arm", "gripper", "camera"]), stop)
    end = (stop + PROBE_S) if stop is not None else t + DRAIN_S
    internal = []
    for s, rqst_id, service, args, u, duration in sorted(sent, key=lambda r: r[4]):
        if u > end or not layer.alive(service, u):
            continue
        layer.take(u, rqst_id, service, args, duration, variant == "telling")
        internal.append((u, "request", rqst_id, service, args, None))
    layer.end_until(end)
    services = {rqst_id: service for _, rqst_id, service, *_ in sent}
    replies = [(e, r, c) for e, r, c in sorted(layer.replies, key=lambda reply: reply[0]) if e <= end]
    internal += [(e, "final", r, services[r], None, c) for e, r, c in replies if c != "taken"]
    observed = [(s, "request", r, service, args, None) for s, r, service, args, *_ in sent]
    arrived = _arrivals([e for e, _, _ in replies], variant == "telling", rng)
    observed += [(o, "taken" if c == "taken" else "final", r, services[r], None, c)
                 for o, (_, r, c) in zip(arrived, replies)]
    trace = Trace(sut=variant, seed=seed, outcome="hung" if stop is not None else "completed")
    trace.events, trace.taken_events = _numbered([e for e in observed if e[0] <= end])
    trace.internal_events, _ = _numbered(internal)
    return trace


def _arrivals(emitted: list[float], one_channel: bool, rng: random.Random) -> list[float]:
    """When each reply (in the order the layer wrote them) is observed: a delay after it left, the
    delays independent, or on one channel never overtaking the reply before."""
    arrived, latest = [], 0.0
    for e in emitted:
        latest = max(latest, e + rng.uniform(0, MAX_DELAY)) if one_channel else e + rng.uniform(0, MAX_DELAY)
        arrived.append(latest)
    return arrived


def _numbered(events: list[tuple]) -> tuple[list[tuple], list[tuple]]:
    """Events in time order, with seq from 1: at the same instant requests first (by id), then replies
    in the order they came; `taken` replies share the counter, as the executive numbers them, and go
    to the second list as (seq, t, rqst_id)."""
    rows = sorted(((t, kind != "request", r if kind == "request" else i), i)
                  for i, (t, kind, r, *_) in enumerate(events))
    logged, taken = [], []
    for seq, (_, i) in enumerate(rows, 1):
        t, kind, r, service, args, reply = events[i]
        module, name = service.split(".")
        if kind == "taken":
            taken.append((seq, t, r))
        else:
            logged.append((seq, t, kind, r, module, name, json.dumps(args) if kind == "request" else None, reply))
    return logged, taken
