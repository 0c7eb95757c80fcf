"""Targeted mutants (`campaign --strategy targeted`): each aims at one property and inserts
requests that make its P-condition false, placed by what the golden run showed.

Generic: it reads only the properties, the interface and the golden run's trace. A property's
basic type says what falsifies its condition (docs/reference/verdicts.md):

- PC[x, Q]: an x sent before every q in Q has ended ok (before q is sent, or while it runs);
- ES[x, y]: an x sent while a y runs;  EE[x, y]: a y sent while an accepted x runs;
- EX = ES and EE; MX_R = ES both ways; MX_I = EE both ways;
- IN[x, Q, Y] (x only inside a span that a q's ok enters and a y's ok leaves): x with a q never
  sent or while it runs, x after a y ended ok, x while a y runs; OUT[x, Q, Y] (x only outside
  every span): x after a q ended ok, x while a q runs;
- VAL[x]: an x whose argument lies outside its domain, anywhere its preconditions hold; with y and
  a narrowed domain, an x legal at rest but outside the narrowed domain, while a y runs
  (harness/mutator/values.py makes the value). Aimed at only with --value-mutations.

"While r runs" is either a place where the golden run had r running (after an optional sleep,
so the activity is past its start), or a fresh r followed, after an optional sleep, by the
request: without the sleep it lands in r's start phase. A fresh request is placed where its own
preconditions hold (the Q of the PC properties it is an x of had ended ok, and the golden run was in
the state its IN and OUT properties need: harness/mutator/states.py), so the layer accepts it.
For EE-type properties a quarter of the aims instead send a request of x's module that does not
dominate x while x runs (an Init during an activity): C stays true, a layer that interrupts
anyway shows a false positive.

Balance: the next mutant aims at the property with the fewest expected falsified requests so far:
the golden run's count of C-false requests times the mutants made, plus the falsifying requests
inserted for it. Every choice draws from random.Random("untimely-targeted:SEED").
"""
from __future__ import annotations

import random
from dataclasses import dataclass
from typing import Callable

from harness.target.interface import Interface, Property
from harness.target.property_types import interruptions
from harness.mutator.operators import Draw, Mutant, plausible, random_request, step_text, validated
from harness.mutator.states import Spans
from harness.target.script import Script, Step
from harness.mutator.timeline import ScriptTimeline
from harness.mutator.values import falsifying_request
from harness.trace import Trace

SITES_PER_MUTANT = 3  # default falsifying insertions per mutant (--ops-per-mutant), at distinct places
DISTURB_SHARE = 0.25  # of the aims at an EE-type property: a non-dominating request instead
START_PHASE_SHARE = 1 / 3  # of the "while r runs" insertions: no sleep, r is still starting
# A sleep before the falsifying request, drawn log-uniformly, and shorter than the shortest
# run the golden showed of the activity it must land in.
SLEEP_RANGE_S = (0.01, 1.0)
VALUE_TYPES = ("VAL",)  # property types whose conditions depend on argument values


@dataclass(frozen=True)
class Falsifier:
    """Send one of `send` before every one of `need` has ended ok (`before_ok`), after one of `need`
    ended ok (`after_ok`), or while one of `running` runs (`during`); `disturb` marks a request that
    leaves C true."""
    kind: str
    send: tuple[str, ...]
    need: tuple[str, ...] = ()
    running: tuple[str, ...] = ()
    disturb: bool = False
    values: dict | None = None  # the request's values must break: {} its own domain, else these narrowed ones


def _ee(x, y) -> Falsifier:
    return Falsifier("during", send=tuple(y), running=tuple(x))


def _es(x, y) -> Falsifier:
    return Falsifier("during", send=tuple(x), running=tuple(y))


def _left(x, leave) -> list[Falsifier]:
    """x once a service that leaves its state ended ok, and while it runs."""
    return [Falsifier("after_ok", send=tuple(x), need=tuple(leave)), _es(x, leave)] if leave else []


def _generic(prop: Property) -> list[Falsifier]:
    """A type without its own aims (a new template): every way its parameters can make a condition
    false, x sent before Q's ok or while a y runs, or while another x runs when it has neither."""
    x, y = prop.x, prop.y
    aims = [Falsifier("before_ok", send=x, need=prop.q)] if prop.q else []
    aims += [_es(x, y), _ee(x, y)] if y else []
    return aims or [_es(x, x)]


# The aims of the paper's types (docs/reference/verdicts.md), by what falsifies each one's condition.
AIMS = {"PC": lambda p: [Falsifier("before_ok", send=p.x, need=p.q)],
        "ES": lambda p: [_es(p.x, p.y)],
        "EE": lambda p: [_ee(p.x, p.y)],
        "EX": lambda p: [_es(p.x, p.y), _ee(p.x, p.y)],
        "MX_R": lambda p: [_es(p.x, p.y), _es(p.y, p.x)],
        "MX_I": lambda p: [_ee(p.x, p.y), _ee(p.y, p.x)],
        "IN": lambda p: [Falsifier("before_ok", send=p.x, need=p.q)] + _left(p.x, p.y),
        "OUT": lambda p: _left(p.x, p.q),
        "VAL": lambda p: [Falsifier("during", send=p.x, running=p.y, values=p.domain) if p.y
                          else Falsifier("anywhere", send=p.x, values={})]}


def falsifiers(prop: Property) -> list[Falsifier]:
    return AIMS.get(prop.type, _generic)(prop)


def disturbers(prop: Property, interface: Interface) -> list[Falsifier]:
    """For each x of a property whose template says its activities may be interrupted (EE, EX,
    MX_I): its module's services that neither are x nor dominate it."""
    if not interruptions().get(prop.type):  # a type without a template here (a Property made in code) has none
        return []
    found = []
    for x in prop.x:
        module = interface.services[x].module
        others = tuple(s for s, svc in interface.services.items()
                       if svc.module == module and s not in prop.y and s not in prop.x)
        if others:
            found.append(Falsifier("during", send=others, running=(x,), disturb=True))
    return found


class Planner:
    """Places falsifying insertions in the golden script, from its run's timeline."""

    def __init__(self, golden: Script, timeline: ScriptTimeline, interface: Interface,
                 properties: list[Property], rng: random.Random):
        self.golden, self.timeline, self.interface, self.rng = golden, timeline, interface, rng
        self.needs: dict[str, set[str]] = {}
        for p in properties:
            if p.type == "PC":
                for x in p.x:
                    self.needs.setdefault(x, set()).update(p.q)
        self.spans = Spans(properties, timeline)  # the states IN and OUT properties need

    def _request(self, service: str, f: Falsifier | None = None) -> Step:
        """A request of `service`, its values legal, or illegal as `f` wants them."""
        spec = self.interface.services[service]
        step = random_request(spec, self.rng, None)
        if f is None or f.values is None:
            return step
        falsified = falsifying_request(step, spec, self.rng, f.values or None)
        return falsified[0] if falsified else step

    def _ready(self, p: int, service: str) -> bool:
        return self.needs.get(service, set()) <= self.timeline.ended_ok(p) and self.spans.hold(p, service)

    def _sleep(self, running: str) -> list[Step]:
        if self.rng.random() < START_PHASE_SHARE:
            return []
        lo, hi = SLEEP_RANGE_S
        runs = [a.end - a.start for a in self.timeline.activities
                if a.service == running and a.accepted and a.end is not None]
        hi = max(lo, min([hi] + [0.9 * d for d in runs]))
        return [Step(0, "sleep", seconds=plausible(lo * (hi / lo) ** self.rng.random()))]

    def site(self, f: Falsifier) -> tuple[int, list[Step], str] | None:
        """(position in the golden, steps to insert there, what it does), or None if impossible."""
        positions, rng = self.timeline.positions, self.rng
        send = rng.choice(f.send)
        if f.kind == "anywhere":
            places = [p for p in positions if self._ready(p, send)] or positions
            return rng.choice(places), [self._request(send, f)], f"{send} with a value outside its domain"
        if f.kind == "before_ok":
            places = [p for p in positions if not set(f.need) <= self.timeline.ended_ok(p)]
            return (rng.choice(places), [self._request(send)],
                    f"{send} before {' and '.join(f.need)} ended ok") if places else None
        if f.kind == "after_ok":
            places = [p for p in positions if set(f.need) & self.timeline.ended_ok(p)]
            return (rng.choice(places), [self._request(send)],
                    f"{send} after {' or '.join(f.need)} ended ok") if places else None
        running = [p for p in positions if self.timeline.running(p, f.running)
                   and self._ready(p, send)]
        if running and rng.random() < 0.5:
            p = rng.choice(running)
            names = sorted({a.service for a in self.timeline.running(p, f.running)})
            return p, self._sleep(names[0]) + [self._request(send, f)], f"{send} while {', '.join(names)} runs"
        fresh = rng.choice(f.running)
        places = [p for p in positions if self._ready(p, fresh)]
        if not places:
            return None
        steps = [self._request(fresh)] + self._sleep(fresh) + [self._request(send, f)]
        phase = " in its start phase" if len(steps) == 2 else ""
        return rng.choice(places), steps, f"{send} while a new {fresh} runs{phase}"

    def mutant(self, prop: Property, options: list[Falsifier], label: str,
               sites_wanted: int) -> tuple[Mutant, int]:
        """A mutant with up to `sites_wanted` insertions aimed at `prop`; and how many of them
        should falsify its condition."""
        sites = []
        for _ in range(sites_wanted):
            found = self.site(self.rng.choice(options))
            if found and found[0] not in {s[0] for s in sites}:
                sites.append(found)
        steps, records, offset = list(self.golden.steps), [], 0
        disturbing = options[0].disturb
        for p, inserted, what in sorted(sites, key=lambda s: s[0]):
            what += " (a disturbance: C stays true)" if disturbing else ""
            steps[p + offset:p + offset] = inserted
            records.append({"op": "insert_request", "aim": prop.id, "situation": what,
                            "position": p + offset + 1, "steps": [step_text(s) for s in inserted]})
            offset += len(inserted)
        falsifying = 0 if disturbing else len(records)
        return validated(Script(tuple(steps), label).renumbered(), records, self.interface), falsifying


@dataclass(frozen=True)
class GoldenRun:
    """The golden script, its run's trace (whose timeline places insertions) and that run's verdicts
    (the P-conditions it falsifies already)."""
    script: Script
    trace: Trace
    verdicts: list[dict]


def generate(golden_run: GoldenRun, interface: Interface, properties: list[Property], draw: Draw,
             name: Callable[[int], str] = "mutant {}".format) -> list[Mutant]:
    """`draw.count` targeted mutants of the golden, balanced over `properties` (see the module doc),
    each with up to `draw.operations` falsifying insertions (SITES_PER_MUTANT by default)."""
    golden, sites, redraws = golden_run.script, draw.operations, draw.redraws
    rng = random.Random(f"untimely-targeted:{draw.seed}")
    planner = Planner(golden, ScriptTimeline(golden, golden_run.trace, interface.replies), interface, properties, rng)
    base = {p.id: 0 for p in properties}
    for v in golden_run.verdicts:
        if v["c_holds"] is False:
            base[v["property_id"]] += 1
    aimed = dict.fromkeys(base, 0)
    seen, mutants = {golden.renumbered().render()}, []
    for n in range(1, draw.count + 1):
        prop = min(properties, key=lambda p: base[p.id] * (n - 1) + aimed[p.id])
        falsify, disturb = falsifiers(prop), disturbers(prop, interface)
        for _ in range(redraws + 1):
            options = disturb if disturb and rng.random() < DISTURB_SHARE else falsify
            mutant, falsifying = planner.mutant(prop, options, name(n), sites)
            if mutant.body not in seen:
                break
        aimed[prop.id] += max(falsifying, 1)  # a disturbing mutant still takes its turn
        seen.add(mutant.body)
        mutants.append(mutant)
    return mutants
