"""Mutation operators over mission scripts (paper §V.C, docs/reference/mission-language.md).

The paper's three operators act on module requests (`send` and `cancel` steps): delete one,
insert an additional one, swap a pair. Two time-domain operators are opt-in: drop a `wait`,
change a `sleep`; so is the value operator replace_value (harness/mutator/values.py). A new
operator is a function (steps, rng, interface) -> record or None (None: it does not apply) added
to the registry OPERATORS; `campaign --operators` picks by name. An operator may produce a script the validator rejects (a `wait` on a
deleted handle, a `wait` or `cancel` moved before its `send`): such a mutant is kept, marked invalid.

Each operation is recorded as a JSON-able dict: `op`, the involved step(s) as text, and
`line`/`lines`, the line numbers of those steps in the golden body (null for a step that
an earlier operation of the same mutant inserted). Every choice draws from the `rng` the
caller passes, so one seed gives byte-identical mutants.
"""
from __future__ import annotations

import random
from dataclasses import dataclass, replace
from typing import Callable, Iterator

from harness.errors import ScriptError, UntimelyError
from harness.target.interface import Interface, Service
from harness.mutator.values import replace_value
from harness.target.script import CANCEL_SUFFIX, Script, Step, cancel_service, step_text, validate

INSERTED_HANDLE_PREFIX = "extra"
REQUEST_STEPS = ("send", "cancel")  # the steps that send a request
# A changed sleep lasts between a tenth and ten times the original (log-uniform).
SLEEP_SCALE_DECADES = 1.0


@dataclass(frozen=True)
class Mutant:
    script: Script
    operations: tuple[dict, ...]
    invalid_reason: str | None = None

    @property
    def valid(self) -> bool:
        return self.invalid_reason is None

    @property
    def body(self) -> str:
        return self.script.render()


def _line(step: Step) -> int | None:
    return step.line or None


def _indices(steps: list[Step], *ops: str) -> list[int]:
    return [i for i, s in enumerate(steps) if s.op in ops]


def plausible(value: float) -> float:
    """Three significant digits: a value a mission author would write."""
    return float(f"{value:.3g}")


def _delete_one(steps, rng, kinds: tuple[str, ...], op: str):
    candidates = _indices(steps, *kinds)
    if not candidates:
        return None
    i = rng.choice(candidates)
    return {"op": op, "line": _line(steps[i]), "step": step_text(steps.pop(i))}


def delete_request(steps, rng, interface):
    return _delete_one(steps, rng, REQUEST_STEPS, "delete_request")


# What an inserted request writes for an argument whose domain offers no value to draw: a number
# without bounds is drawn from UNBOUNDED, a required text without choices is PLAIN_TEXT (an
# optional one is left out).
UNBOUNDED = (-10.0, 10.0)
PLAIN_TEXT = "value"


def random_request(service: Service, rng: random.Random, handle: str | None) -> Step:
    """A request of `service` with values drawn from its arguments' domains."""
    args = []
    for arg in service.args.values():
        if arg.type == "float":
            low = arg.min if arg.min is not None else min(UNBOUNDED[0], arg.max if arg.max is not None else 0.0)
            high = arg.max if arg.max is not None else max(UNBOUNDED[1], low)
            args.append((arg.name, f"{plausible(rng.uniform(low, high)):g}"))
        elif arg.choices:
            args.append((arg.name, rng.choice(arg.choices)))
        elif arg.required:
            args.append((arg.name, PLAIN_TEXT))
    return Step(0, "send", service=service.qualified, args=tuple(args), handle=handle)


def _fresh_handle(steps: list[Step]) -> str:
    taken = {s.handle for s in steps}
    n = 1
    while f"{INSERTED_HANDLE_PREFIX}{n}" in taken:
        n += 1
    return f"{INSERTED_HANDLE_PREFIX}{n}"


def insert_request(steps, rng, interface):
    """A request of a service drawn from the interface at a drawn position; a request of a goal's
    cancel service (M.S_cancel) is a `cancel` of an earlier goal of M.S that has a handle, where
    one has (else a plain send of the cancel service, as a script may write it)."""
    service = interface.services[rng.choice(sorted(interface.services))]
    handle = _fresh_handle(steps) if rng.random() < 0.5 else None
    step = random_request(service, rng, handle)
    at = rng.randint(0, len(steps))
    goals = [s.handle for s in steps[:at] if s.op == "send" and s.handle
             and s.service + CANCEL_SUFFIX == service.qualified]
    if goals:
        step = Step(0, "cancel", handle=handle, cancelled=rng.choice(goals))
    steps.insert(at, step)
    return {"op": "insert_request", "position": at + 1, "step": step_text(step)}


def as_cancel(steps: list[Step], sent: Step) -> tuple[list[Step], Step]:
    """A request of a goal's cancel service, to come after `steps`, written as a `cancel` of the
    latest goal of that service they send (given a handle if it has none), so that a test and its
    reproducer say which goal it cancels; any other request as it is."""
    goal = next((s for s in reversed(steps) if s.op == "send" and cancel_service(s.service) == sent.service), None)
    if goal is None or sent.args:
        return steps, sent
    handle = goal.handle or "goal"
    return [replace(s, handle=handle) if s is goal else s for s in steps], Step(0, "cancel", cancelled=handle)


def swap_requests(steps, rng, interface):
    sends = _indices(steps, *REQUEST_STEPS)
    if len(sends) < 2:
        return None
    i, j = sorted(rng.sample(sends, 2))
    steps[i], steps[j] = steps[j], steps[i]
    return {"op": "swap_requests", "lines": [_line(steps[j]), _line(steps[i])],
            "steps": [step_text(steps[j]), step_text(steps[i])]}


def drop_wait(steps, rng, interface):
    return _delete_one(steps, rng, ("wait",), "drop_wait")


def change_sleep(steps, rng, interface):
    sleeps = _indices(steps, "sleep")
    if not sleeps:
        return None
    i = rng.choice(sleeps)
    old = steps[i]
    seconds = plausible(old.seconds * 10 ** rng.uniform(-SLEEP_SCALE_DECADES, SLEEP_SCALE_DECADES))
    steps[i] = replace(old, seconds=seconds)
    return {"op": "change_sleep", "line": _line(old), "step": step_text(old), "seconds": seconds}


# The registry: every operator by name, in the order a mutant draws among those it may use.
OPERATORS = {op.__name__: op for op in (delete_request, insert_request, swap_requests, drop_wait, change_sleep,
                                         replace_value)}
REQUEST_OPERATORS = ("delete_request", "insert_request", "swap_requests")  # the paper's, the default
TIME_OPERATORS = ("drop_wait", "change_sleep")  # added by --time-mutations
VALUE_OPERATORS = ("replace_value",)  # added by --value-mutations


def chosen(names: str | None, time_mutations: bool = False, value_mutations: bool = False) -> tuple[str, ...]:
    """The operators a campaign draws among: those named (`campaign --operators a,b`), in the
    registry's order, or the paper's, with the time-domain ones for --time-mutations and the
    value one for --value-mutations."""
    if names is None:
        return REQUEST_OPERATORS + (TIME_OPERATORS if time_mutations else ()) + \
            (VALUE_OPERATORS if value_mutations else ())
    given = [n.strip() for n in names.split(",") if n.strip()]
    unknown = [n for n in given if n not in OPERATORS]
    if unknown or not given:
        raise UntimelyError(f"--operators {names!r}: {'no operator ' + repr(unknown[0]) if unknown else 'none named'}; "
                            f"give a comma-separated list of {', '.join(OPERATORS)}")
    if time_mutations or value_mutations:
        raise UntimelyError(f"--{'time' if time_mutations else 'value'}-mutations adds "
                            f"{' and '.join(TIME_OPERATORS if time_mutations else VALUE_OPERATORS)} to the default "
                            "operators; with --operators, name them in its list instead")
    return tuple(n for n in OPERATORS if n in given)


def mutate(golden: Script, interface: Interface, rng: random.Random, operations: int = 1,
           label: str = "mutant", operators: tuple[str, ...] | None = None) -> Mutant:
    """Apply `operations` operators drawn uniformly among those that apply (of `operators`, by
    default chosen(None)), then validate. An operation none of them applies to is left out
    (insert_request always applies)."""
    steps, records = list(golden.steps), []
    names = chosen(None) if operators is None else operators
    for _ in range(operations):
        candidates = [OPERATORS[n] for n in names]
        record = None
        while record is None and candidates:
            operator = rng.choice(candidates)
            candidates.remove(operator)
            record = operator(steps, rng, interface)
        if record is not None:
            records.append(record)
    return validated(Script(tuple(steps), label).renumbered(), records, interface)


def validated(script: Script, records: list[dict], interface: Interface) -> Mutant:
    """The mutant, marked invalid with the validator's message if the interface cannot run it."""
    try:
        validate(script, interface)
    except ScriptError as e:
        return Mutant(script, tuple(records), str(e))
    return Mutant(script, tuple(records))


@dataclass(frozen=True)
class Draw:
    """What a generation draws: `count` mutants from `seed`, each of `operations` operations (the
    targeted strategy's insertion sites) of `operators` (default chosen(None, time_mutations)); a
    mutant equal to the golden or an earlier one is redrawn up to `redraws` times."""
    count: int
    seed: int
    operations: int = 1
    time_mutations: bool = False
    operators: tuple[str, ...] | None = None
    redraws: int = 50

    def names(self) -> tuple[str, ...]:
        return chosen(None, self.time_mutations) if self.operators is None else self.operators


def generate(golden: Script, interface: Interface, draw: Draw,
             name: Callable[[int], str] = "mutant {}".format) -> Iterator[Mutant]:
    """`draw.count` seeded mutants, one at a time (a caller shows its progress); `name(n)` labels
    the n-th (from 1) in its validator message. A mutant whose body equals the golden or an
    earlier mutant's is redrawn, so duplicates only remain when the operators run out of
    distinct mutants."""
    names = draw.names()
    if draw.count and not any(OPERATORS[n](list(golden.steps), random.Random(0), interface) for n in names):
        # every "mutant" would be the golden script itself
        raise UntimelyError(f"--operators {','.join(names)}: none of them finds a step to change in the golden "
                            f"script {golden.source}, so every mutant would be the golden script; name others "
                            f"among {', '.join(OPERATORS)}")
    rng = random.Random(f"untimely-mutants:{draw.seed}")
    seen = {golden.renumbered().render()}
    for n in range(1, draw.count + 1):
        for _ in range(draw.redraws + 1):
            mutant = mutate(golden, interface, rng, draw.operations, name(n), names)
            if mutant.body not in seen:
                break
        seen.add(mutant.body)
        yield mutant
