"""The states a request needs, from the span properties (IN, OUT: sql/oracles/in.sql, out.sql) and
the golden run: which services must have ended ok first to put the target in the state where a
request is accepted, and which ones leave that state.

An IN[x, Q, Y] property says x is accepted only inside a span that an ok of a q enters and an ok of
a y leaves (a lifecycle node's goals only while active: Q = {activate}); an OUT property the same
outside every span (the trace starts there: Q enters the span, so Y re-enters the outside). Unlike
PC's Q (every q ended ok), one entry suffices, and which one is the golden's: the entering service
whose ok was the latest of the span's services before the golden's first send of x (activate
enters "inactive" from configure on the way up, from deactivate on the way down). A golden that
never sends x, or sends it outside its state, gives the first entering service the golden ends ok,
else the first one named. A targeted mutant's fresh request goes where the golden run was in its
state (`Spans.hold`). Generic: only the properties and the golden run's timeline are read.
"""
from __future__ import annotations

from harness.mutator.timeline import ScriptTimeline
from harness.target.interface import Property

# type -> (inside the span: x accepted there; False: x accepted outside it, where a trace starts)
SPANS = {"IN": True, "OUT": False}


def _enter_leave(prop: Property) -> tuple[tuple[str, ...], tuple[str, ...]]:
    """The services whose ok enters the state x needs, and those whose ok leaves it."""
    return (prop.q, prop.y) if SPANS[prop.type] else (prop.y, prop.q)


def entry_needs(properties: list[Property], timeline: ScriptTimeline) -> dict[str, set[str]]:
    """Service -> the services one of which (the golden's) must end ok to put it in its state."""
    needs: dict[str, set[str]] = {}
    for prop in (p for p in properties if p.type in SPANS):
        enter, leave = _enter_leave(prop)
        for x in prop.x:
            entry = _golden_entry(timeline, x, enter, leave, starts_inside=not SPANS[prop.type])
            if entry and entry != x:
                needs.setdefault(x, set()).add(entry)
    return needs


def _latest_ok(timeline: ScriptTimeline, services, before_t: float, step: int):
    """The last of `services` whose ok the golden observed before `before_t`, sent before `step`."""
    oks = [a for a in timeline.activities if a.step < step and a.reply == "ok" and a.end is not None
           and a.end < before_t and a.service in services]
    return max(oks, key=lambda a: a.end, default=None)


def _golden_entry(timeline: ScriptTimeline, x: str, enter, leave, starts_inside: bool) -> str | None:
    first = next((a for a in timeline.activities if a.service == x), None)
    if first is not None:
        latest = _latest_ok(timeline, (*enter, *leave), first.start, first.step)
        if latest is None and starts_inside:
            return None
        if latest is not None and latest.service in enter:
            return latest.service
    if starts_inside:  # the golden sent x after leaving its state: the trace's start is that state
        return None
    return next((a.service for a in timeline.activities if a.service in enter and a.reply == "ok"),
                enter[0] if enter else None)


def leavers(properties: list[Property]) -> dict[str, set[str]]:
    """Service -> the services whose ok leaves the state it needs (a context for it leaves them out)."""
    found: dict[str, set[str]] = {}
    for prop in (p for p in properties if p.type in SPANS):
        for x in prop.x:
            found.setdefault(x, set()).update(_enter_leave(prop)[1])
    return found


class Spans:
    """Where in the golden run each service is in the state its span properties need."""

    def __init__(self, properties: list[Property], timeline: ScriptTimeline):
        self.timeline = timeline
        self.of: dict[str, list[tuple]] = {}  # x -> (entering, leaving, starts inside) per property
        for prop in (p for p in properties if p.type in SPANS):
            for x in prop.x:
                self.of.setdefault(x, []).append((*_enter_leave(prop), not SPANS[prop.type]))

    def hold(self, p: int, service: str) -> bool:
        """Whether, at position p, the latest ok among each span's services is an entry (or there is
        none, where the state is the trace's start)."""
        for enter, leave, starts_inside in self.of.get(service, ()):
            latest = _latest_ok(self.timeline, (*enter, *leave), self.timeline.start[p], p)
            if not (latest.service in enter if latest else starts_inside):
                return False
        return True
