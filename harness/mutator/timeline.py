"""What a script's run shows about timing, step by step: which activities run, which services
have ended ok, at each place a step could be inserted.

Read from the golden run's observed events, black-box: a `send` or `cancel` step is observed at
its request's time (a cancel's is a request of its cancel service); a `sleep` lasts its seconds; a
`wait` ends when the awaited final replies are observed, plus the executive's reaction time.
Position p is the place before step p (p = number of steps means the end of the script).
"""
from __future__ import annotations

from dataclasses import dataclass

from harness.sut.executive import REACTION_S
from harness.target.script import Script, cancel_service
from harness.trace import Trace


@dataclass(frozen=True)
class ScriptActivity:
    """A request of a script as its run's trace shows it: when it was sent, and its final reply."""
    service: str  # "module.Service"
    step: int  # index of its send step
    start: float
    end: float | None  # when its final reply was observed; None if it never got one
    reply: str | None
    accepted: bool  # its final reply (if any) is not a rejection


class ScriptTimeline:
    """A script's requests on the timeline of its run (the golden's, for the mutators)."""

    def __init__(self, script: Script, trace: Trace, reply_classes: dict[str, str]):
        requests, finals = {}, {}
        for _seq, t, kind, rqst_id, module, service, _args, reply in trace.events:
            if kind == "request":
                requests[rqst_id] = t
            elif kind == "final" and rqst_id not in finals:
                finals[rqst_id] = (t, reply)
        self.activities: list[ScriptActivity] = []
        self.start: list[float] = []  # start[p]: when the executive reaches position p
        now, by_handle = 0.0, {}
        for index, step in enumerate(script.steps):
            self.start.append(now)
            if step.op in ("send", "cancel"):
                rqst_id = len(self.activities) + 1
                end, reply = finals.get(rqst_id, (None, None))
                now = requests.get(rqst_id, now)
                self.start[-1] = now
                service = step.service if step.op == "send" else cancel_service(by_handle[step.cancelled].service)
                activity = ScriptActivity(service, index, now, end, reply, reply_classes.get(reply) != "R")
                self.activities.append(activity)
                if step.handle:
                    by_handle[step.handle] = activity
            elif step.op == "sleep":
                now += step.seconds
            else:
                awaited = self.activities if step.handle == "all" else [by_handle[step.handle]]
                ends = [a.end for a in awaited if a.end is not None]
                now = max([now] + ends) + REACTION_S
        self.start.append(now)
        self._ended_ok = [self._ok_before(p) for p in self.positions]

    @property
    def positions(self) -> range:
        return range(len(self.start))

    def running(self, p: int, services) -> list[ScriptActivity]:
        """Accepted activities of `services` sent before position p, not yet ended there."""
        at = self.start[p]
        return [a for a in self.activities if a.service in services and a.step < p and a.accepted
                and (a.end is None or a.end > at)]

    def ended_ok(self, p: int) -> set[str]:
        """The services with an `ok` final reply observed before position p is reached."""
        return self._ended_ok[p]

    def _ok_before(self, p: int) -> set[str]:
        at = self.start[p]
        return {a.service for a in self.activities
                if a.step < p and a.reply == "ok" and a.end is not None and a.end < at}
