"""Focused tests (`campaign --strategy focused`): each test carries only the context its aim needs.

An aim is one way to falsify (or, for a disturbance, to probe) a property's P-condition, as
targeted.py lists them (falsifiers, disturbers): send s before a service q has ended ok, or
send s while an activity r runs; for a value-domain property (only with --value-mutations),
send s with one exceptional value of one argument (harness.mutator.values.cases: one aim per
value, those inside the domain disturbances), anywhere, or, for a state-dependent domain, while
r runs. A test for it is
  1. the context: the golden script's sends of the services s and r need (their modules' inits,
     the Q of the PC properties naming them, the golden's entry into the state an IN or OUT property
     needs: harness.mutator.states; transitively), less those leaving the state r needs, in the golden's
     order, with the golden's waits on them given a timeout (twice the longest run the golden showed,
     plus a second). A module's inits need each other (each is an init of the others' module):
     that cycle is sent in the golden's order too; a cycle of PC properties alone (x needs q ok
     before, q needs x) is refused, as no service of it can be sent first;
  2. the perturbation: s alone (q never sent, or s with its exceptional value, or after q in the
     context ended ok: an IN or OUT property's state left), q then s (s lands while q runs), r
     then s (in r's start phase), or r, a sleep shorter than r's shortest golden run, then s;
  3. after SETTLE_S, the request that ended r or s in the golden run if it never ends by itself
     (the golden's Stop); then the executive's drain (DRAIN_S) awaits the outstanding finals.
So a test's mission time has an upper bound known before it runs (script_time.bound_s), which is what
lets a campaign keep within its budget (harness.campaign.budget).

Generic: only the interface, the properties and the golden script and run are read.
Test n is the n-th aim for n < len(aims) (every aim once, properties interleaved), then the
timed aims (those whose outcome depends on when s lands) again and again, each repeat drawing
another delay. Every choice of test n draws from random.Random("untimely-focused:SEED:n"), so
a resumed campaign makes the same tests.
"""
from __future__ import annotations

import random
from dataclasses import dataclass
from itertools import zip_longest

from harness.errors import UntimelyError
from harness.target.interface import Interface, Property
from harness.target.mission import PROPERTIES_FILE
from harness.mutator.operators import Mutant, as_cancel, plausible, random_request, step_text, validated
from harness.mutator.states import entry_needs, leavers
from harness.mutator.targeted import Falsifier, disturbers, falsifiers
from harness.mutator.timeline import ScriptTimeline
from harness.mutator.values import cases, with_value
from harness.mutator.script_time import bound_s, least_s
from harness.target.script import Script, Step

UNSEEN_RUN_S = 5.0  # how long an activity the golden never ran is awaited
# A start-phase (or "while q runs") aim sleeps FIRST_SLEEP_S, longer than the interface's delays so
# the layer gets r before s, and the observed timeline orders them; its repeats draw log-uniformly.
FIRST_SLEEP_S = 0.01
START_SLEEP_S = (0.005, 0.1)
RUN_SLEEP_S = (0.01, 1.0)  # a running-phase sleep, log-uniform, below the shortest golden run
SETTLE_S = 1.0  # after the perturbation, before ending the activities that never end by themselves
SHOWN_CHARS = 20  # of an exceptional value, in a situation (an over-long text is cut)


@dataclass(frozen=True)
class Aim:
    properties: tuple[str, ...]  # the properties whose condition it falsifies (or probes)
    send: str  # s
    phase: str  # "without" q, "during" q, "after" q ended ok, r's "start", r "running", or a "value" alone
    other: str  # q or r ("" for a value alone)
    disturb: bool = False
    value: tuple[str, str, str | None] | None = None  # s's (argument, class, word; None: left out)

    @property
    def timed(self) -> bool:
        return self.phase not in ("without", "after", "value")

    def situation(self) -> str:
        what = {"without": "{s} with {o} never sent", "during": "{s} while {o} runs (before it ended ok)",
                "after": "{s} after {o} ended ok", "start": "{s} in the start phase of {o}",
                "running": "{s} while {o} runs", "value": "{s}"}[self.phase]
        send = self.send
        if self.value:
            argument, kind, word = self.value
            shown = word if word is None or len(word) <= SHOWN_CHARS else f"{word[:SHOWN_CHARS]}..."
            send += f" with {argument} left out" if word is None else f" with {argument}={shown} ({kind})"
        return what.format(s=send, o=self.other) + (" (a disturbance: C stays true)" if self.disturb else "")


def _value_keys(f: Falsifier, service: str, interface: Interface) -> list[tuple]:
    """The aims of a value-domain falsifier at `service`: one per distinct exceptional value of
    each argument its domain constrains (outside it: falsifying; inside: a disturbance), alone
    or, for a narrowed domain, in the start phase of and while each r runs."""
    values: dict[tuple, tuple] = {}
    for arg in interface.services[service].args.values():
        if not f.values or arg.name in f.values:
            for kind, word, breaks in cases(arg, f.values.get(arg.name) if f.values else None):
                values.setdefault((arg.name, word), ((arg.name, kind, word), breaks))
    places = [("value", "")] if f.kind == "anywhere" else [(phase, r) for r in f.running
                                                          for phase in ("start", "running")]
    return [(service, phase, other, not breaks, value) for value, breaks in values.values() for phase, other in places]


def aims(properties: list[Property], interface: Interface) -> list[Aim]:
    """Every aim once, properties interleaved (the first aim of each, then the second...); an aim
    serving several properties is listed once, under all of them."""
    per_property: list[list[tuple]] = []
    for prop in properties:
        keys = []
        for f in falsifiers(prop) + disturbers(prop, interface):
            for s in f.send:
                if f.values is not None:
                    keys += _value_keys(f, s, interface)
                elif f.kind == "before_ok":
                    keys += [(s, phase, q, f.disturb, None) for q in f.need for phase in ("without", "during")]
                elif f.kind == "after_ok":
                    keys += [(s, "after", q, f.disturb, None) for q in f.need]
                else:
                    keys += [(s, phase, r, f.disturb, None) for r in f.running for phase in ("start", "running")]
        per_property.append([(prop.id, k) for k in keys])
    served: dict[tuple, list[str]] = {}
    for column in zip_longest(*per_property):
        for pid, key in filter(None, column):
            served.setdefault(key, []).append(pid)
    return [Aim(tuple(dict.fromkeys(pids)), *key) for key, pids in served.items()]


class Builder:
    """Writes the test of an aim from the golden script and its run's timeline."""

    def __init__(self, golden: Script, timeline: ScriptTimeline, interface: Interface, properties: list[Property],
                 source: str = PROPERTIES_FILE):
        self.golden, self.interface, self.source = golden, interface, source
        # A service needs its module's inits (the interface names them) and the Q of the PC
        # properties naming it (`declared`: which property says x needs q).
        self.needs: dict[str, set[str]] = {s: {i for i in interface.of_kind("init") if i != s
                                               and interface.services[i].module == svc.module}
                                           for s, svc in interface.services.items()}
        self.declared: dict[tuple[str, str], str] = {}
        for p in properties:
            if p.type == "PC":
                for x in p.x:
                    self.needs.setdefault(x, set()).update(p.q)
                    self.declared.update({(x, q): p.id for q in p.q if (x, q) not in self.declared})
        # ... and the service whose ok put it in the state an IN or OUT property needs, the golden's way,
        # without those that leave that state (harness.mutator.states).
        for x, entries in entry_needs(properties, timeline).items():
            self.needs.setdefault(x, set()).update(entries)
        self.leaves = leavers(properties)
        self.runs: dict[str, list[float]] = {}
        for a in timeline.activities:
            if a.accepted and a.end is not None:
                self.runs.setdefault(a.service, []).append(a.end - a.start)
        # What ended each activity that never ends by itself, in the golden run: the last request
        # of its module sent before its end (the golden's Stop).
        self.enders: dict[str, str] = {}
        for a in timeline.activities:
            if a.service in interface.until_stopped and a.accepted and a.end is not None:
                module = interface.services[a.service].module
                before = [b for b in timeline.activities if b is not a and b.start <= a.end
                          and b.step > a.step and interface.services[b.service].module == module]
                if before:
                    self.enders.setdefault(a.service, before[-1].service)

    def closure(self, services, without: str | None = None) -> list[str]:
        """The services that must have ended ok before `services` are sent, transitively;
        `without`: leave out that one and whatever needs it."""
        found: list[str] = []
        visiting: list[str] = []  # the services whose needs are being visited, outermost first

        def visit(service: str) -> bool:
            if service == without:
                return False
            if service in visiting:  # a cycle: its services are all wanted, sent in the golden's order
                self._check_cycle(visiting[visiting.index(service):] + [service])
                return True
            visiting.append(service)
            needed = [visit(q) for q in sorted(self.needs.get(service, ()))]
            visiting.pop()
            if not all(needed):
                return False
            if service not in found:
                found.append(service)
            return True
        for service in services:
            for q in sorted(self.needs.get(service, ())):
                visit(q)
        return found

    def _check_cycle(self, cycle: list[str]) -> None:
        """A cycle that module inits close (each needs the others) has an order, the golden's; one
        of PC properties alone has none: refused, naming its properties and their file."""
        edges = list(zip(cycle, cycle[1:]))
        if all(edge in self.declared for edge in edges):
            says = "; ".join(f"{self.declared[(x, q)]} makes {x} need {q} ok before it" for x, q in edges)
            raise UntimelyError(f"{self.source}: the PC properties need each other in a cycle, "
                                f"{' -> '.join(cycle)} ({says}), so no service of it can be sent first and no "
                                "focused test can set it up; remove the Q of one of them (or fix the golden and "
                                "the properties to the order the layer really needs)")

    def _timeout(self, services) -> float:
        longest = max([max(self.runs.get(s, [UNSEEN_RUN_S])) for s in services] + [0.0])
        return plausible(2 * longest + 1.0)

    def request(self, service: str, rng: random.Random, handle: str | None = None, value=None) -> Step:
        """The golden's first request of `service` (its arguments), else one with drawn arguments;
        `value` (argument, class, word): with that argument written as the word."""
        sent = next((s for s in self.golden.steps if s.op == "send" and s.service == service), None)
        step = sent or random_request(self.interface.services[service], rng, None)
        step = Step(0, "send", service=service, args=step.args, handle=handle)
        return with_value(step, value[0], value[2]) if value else step

    def context(self, wanted: list[str], rng: random.Random) -> list[Step]:
        """Sends of the `wanted` services in the golden's order, each awaited (with a timeout)
        before anything sent after the golden's wait on it."""
        steps, pending, sent = [], [], set()
        for step in self.golden.steps:
            if step.op == "send" and step.service in wanted and step.service not in sent:
                handle = f"c{len(sent) + 1}"
                steps.append(Step(0, "send", service=step.service, args=step.args, handle=handle))
                pending.append((handle, step.service, step.handle))
                sent.add(step.service)
            elif step.op == "wait" and pending:
                awaited = [p for p in pending if step.handle in ("all", p[2])]
                steps += self._waits(awaited)
                pending = [p for p in pending if p not in awaited]
        steps += self._waits(pending)
        for service in wanted:  # a service the golden never sends: a fresh request, awaited
            if service not in sent:
                handle = f"c{len(sent) + 1}"
                steps += [self.request(service, rng, handle)] + self._waits([(handle, service, None)])
                sent.add(service)
        return steps

    def _waits(self, awaited) -> list[Step]:
        return [Step(0, "wait", handle=h, seconds=self._timeout([s])) for h, s, _ in awaited]

    def sleep(self, aim: Aim, rng: random.Random, repeat: bool) -> list[Step]:
        if not aim.timed:
            return []
        if aim.phase in ("start", "during") and not repeat:
            return [Step(0, "sleep", seconds=FIRST_SLEEP_S)]
        lo, hi = START_SLEEP_S if aim.phase == "start" else RUN_SLEEP_S
        if aim.phase != "start":
            hi = max(lo, min([hi] + [0.9 * d for d in self.runs.get(aim.other, [])]))
        return [Step(0, "sleep", seconds=plausible(lo * (hi / lo) ** rng.random()))]

    def running_context(self, aim: Aim, wanted: list[str]) -> list[str]:
        """`wanted` without the services that leave the state r (the activity that must run: the aim's
        other) needs, unless r's own context has them (it left that state and came back)."""
        own = self.closure([aim.other])
        return [s for s in wanted if s in own or s not in self.leaves.get(aim.other, ())]

    def test(self, aim: Aim, rng: random.Random, repeat: bool) -> list[Step]:
        if aim.phase in ("value", "after"):  # q's context and q (awaited) before s
            after = [aim.other] if aim.phase == "after" else []
            steps = self.context(self.closure([aim.send, *after]) + after, rng)
        elif aim.phase in ("without", "during"):
            wanted = self.closure([aim.send], without=aim.other)
            if aim.phase == "during":
                wanted = self.running_context(aim, wanted + [s for s in self.closure([aim.other]) if s not in wanted])
            steps = self.context(wanted, rng)
            if aim.phase == "during":
                steps += [self.request(aim.other, rng)]
        else:
            steps = self.context(self.running_context(aim, self.closure([aim.send, aim.other])), rng)
            steps += [self.request(aim.other, rng)]
        steps, sent = as_cancel(steps, self.request(aim.send, rng, value=aim.value))
        steps += self.sleep(aim, rng, repeat) + [sent]
        enders = list(dict.fromkeys(self.enders[s] for s in (aim.other, aim.send) if s in self.enders))
        if enders:  # else the drain would wait its full time for an activity that never ends
            steps += [Step(0, "sleep", seconds=SETTLE_S)] + [self.request(e, rng) for e in enders]
        return steps


class Plan:
    """The campaign's tests in order (see the module doc)."""

    def __init__(self, golden: Script, timeline: ScriptTimeline, interface: Interface, properties: list[Property],
                 seed: int, source: str = PROPERTIES_FILE):
        """`source`: the properties' file, named when they need each other in a cycle."""
        self.aims = aims(properties, interface)
        self.timed = [a for a in self.aims if a.timed]
        self.builder = Builder(golden, timeline, interface, properties, source)
        self.interface, self.seed = interface, seed
        for service in interface.services:  # a cycle of properties is refused before any test runs
            self.builder.closure([service])

    def aim(self, n: int) -> tuple[Aim, int]:
        """Test n's aim and its round (0: the aim's first test)."""
        if n < len(self.aims) or not self.timed:
            return self.aims[n % len(self.aims)], n // len(self.aims)
        k = n - len(self.aims)
        return self.timed[k % len(self.timed)], 1 + k // len(self.timed)

    def test(self, n: int, label: str) -> Mutant:
        aim, round_ = self.aim(n)
        rng = random.Random(f"untimely-focused:{self.seed}:{n}")
        steps = self.builder.test(aim, rng, repeat=round_ > 0)
        record = {"op": "focused", "test": n, "aim": aim.properties[0], "properties": list(aim.properties),
                  "situation": aim.situation(), "round": round_, "steps": [step_text(s) for s in steps]}
        return validated(Script(tuple(steps), label).renumbered(), [record], self.interface)
