"""Seeded random traces of the ROS 2 arm of tests/traces/ros2_arm, on two timelines: the server's
(internal: when it took each request and sent each reply) and the bench's (observed: each request
sent up to DELAY_S before the server took it, each reply received up to DELAY_S after it left).
Goals, cancels, calls and transitions come often within a few milliseconds of each other and of
the deadlines; a fifth of the traces hang, losing the replies still on their way and the requests
not yet taken. No semantics is kept (any reply may follow any request): the oracles' alternatives
must hold whatever the server did (tests/analysis/test_ros2_types.py)."""
from __future__ import annotations

import json
import random

from harness.trace import Trace

DELAY_S = 0.003
# service -> (chance of a final reply, its codes, how long it may take: a short and a long bound)
REPLIES = {"move": (0.85, ("ok", "aborted", "canceled", "rejected"), (0.01, 2.0)),
           "move_cancel": (0.9, ("ok", "rejected", "goal_terminated"), (0.01, 1.5)),
           "grip": (0.9, ("ok", "refused"), (0.02, 1.0)),
           "deactivate": (0.95, ("ok", "refused"), (0.02, 0.3)),
           "cleanup": (0.95, ("ok",), (0.02, 0.3))}
SERVICES = ("move", "move", "move", "move_cancel", "move_cancel", "grip", "deactivate", "cleanup")


def _replies(rng: random.Random, service: str, taken: float) -> list[tuple[float, str, str | None]]:
    chance, codes, bounds = REPLIES[service]
    replies = []
    if service == "move" and rng.random() < 0.5:
        replies.append((taken + rng.uniform(0, 0.8), "intermediate", None))
    if rng.random() < chance:
        near = rng.random() < 0.3  # near one of the deadlines (0.5 s, 1 s) of the arm's properties
        after = rng.choice((0.5, 1.0)) + rng.uniform(-0.008, 0.008) if near else rng.uniform(0, rng.choice(bounds))
        replies.append((taken + max(after, 0.0), "final", rng.choice(codes)))
    return sorted(replies, key=lambda r: (r[0], r[1] == "final"))


def random_arm_trace(seed: int) -> Trace:
    rng = random.Random(f"ros2-fuzz:{seed}")
    internal, observed, goals, t = [], [], [], 0.0
    for rqst_id in range(1, rng.randint(2, 7) + 1):
        t += rng.uniform(0, 0.012) if rng.random() < 0.5 else rng.uniform(0.01, 0.7)
        service = rng.choice(SERVICES)
        args = {}
        if service == "move":
            args, goals = {"goal": float(rqst_id)}, goals + [rqst_id]
        elif service == "move_cancel" and goals and rng.random() < 0.3:
            args = {"goal": float(rng.choice(goals))}
        row = ("request", rqst_id, "arm", service, json.dumps(args), None)
        internal.append((t, *row))
        observed.append((t - rng.uniform(0, DELAY_S), *row))
        for at, kind, code in _replies(rng, service, t):
            internal.append((at, kind, rqst_id, "arm", service, None, code))
            observed.append((at + rng.uniform(0, DELAY_S), kind, rqst_id, "arm", service, None, code))
    hung = rng.random() < 0.2
    last = max(e[0] for e in observed)
    end = rng.uniform(t, last + 0.01) if hung else last + rng.choice((0.0, rng.uniform(0, 1.5)))
    trace = Trace(sut=rng.choice(("arm-a", "arm-b")), seed=seed, outcome="hung" if hung else "completed", sim_s=end)
    trace.internal_events, trace.events = (_numbered([e for e in events if e[0] <= end])
                                           for events in (internal, observed))
    return trace


def _numbered(events: list[tuple]) -> list[tuple]:
    """In order of time (a request before the replies it got at the same instant), seq 1, 2, ..."""
    ordered = sorted(events, key=lambda e: (e[0], e[1] != "request"))
    return [(seq, t, kind, rqst_id, module, service, args, reply)
            for seq, (t, kind, rqst_id, module, service, args, reply) in enumerate(ordered, 1)]
