"""Value mutations (`campaign --value-mutations`, docs/generation.md): Ballista-style exceptional
values for one argument of one request, chosen from its type and its interface domain.

A float argument gets each bound, just outside each bound, zero, a negative number, nan, the
infinities, a word that is no number; a text argument the empty text, an over-long text, a number,
a word that is not among its choices; a required argument may be left out. Some of these lie in
the domain (a bound, zero within the range): the layer must accept those, and a layer that refuses
them shows a false positive. A mutant stays a runnable script: the words are written as the mission
language carries them (harness/target/domains.py), the layer is what must refuse them.

Operations are recorded like the timing operators': `op` = replace_value, the golden `line` and
`step`, the `argument`, its `class` (e.g. above_max) and the `value` written (null when left out).
"""
from __future__ import annotations

import random
from dataclasses import replace

from harness.target.domains import EMPTY_TEXT, Argument, Domain, violation
from harness.target.interface import Interface, Service
from harness.target.script import Step, step_text

LONG_TEXT_CHARS = 300  # longer than any name a layer should take
WRONG_TYPE = {"float": "abc", "str": "0"}  # a word of the other type
OUTSIDE_SHARE = 1000  # just outside a bound: by a thousandth of the range (or of the bound)


def _word(value: float) -> str:
    return f"{value:.6g}"


def _step_out(arg: Argument, domain: Domain) -> float:
    if domain.min is not None and domain.max is not None and domain.max > domain.min:
        return (domain.max - domain.min) / OUTSIDE_SHARE
    bound = domain.min if domain.min is not None else domain.max
    return max(abs(bound or 0.0), 1.0) / OUTSIDE_SHARE


def exceptional_values(arg: Argument, domain: Domain | None = None) -> list[tuple[str, str | None]]:
    """(class, word) of each exceptional value of `arg` against `domain` (default: its own);
    word None = the argument left out."""
    domain = domain or arg.domain
    found = []
    if arg.type == "float":
        delta = _step_out(arg, domain)
        if domain.min is not None:
            found += [("min", _word(domain.min)), ("below_min", _word(domain.min - delta))]
        if domain.max is not None:
            found += [("max", _word(domain.max)), ("above_max", _word(domain.max + delta))]
        largest = max(abs(domain.min or 0.0), abs(domain.max or 0.0), 1.0)
        found += [("zero", "0"), ("negative", _word(-largest)), ("nan", "nan"), ("inf", "inf"), ("-inf", "-inf")]
    else:
        found += [("empty", EMPTY_TEXT), ("too_long", "a" * LONG_TEXT_CHARS)]
        if domain.choices:
            found.append(("not_a_choice", "unknown"))
    found.append(("wrong_type", WRONG_TYPE[arg.type]))
    if arg.required:
        found.append(("missing", None))
    return found


def with_value(step: Step, name: str, word: str | None) -> Step:
    """The step with argument `name` written as `word` (None: left out), in its place or at the end."""
    args = [(n, w) for n, w in step.args if n != name or word is not None]
    if word is not None:
        args = [(n, word if n == name else w) for n, w in args]
        if name not in dict(step.args):
            args.append((name, word))
    return replace(step, args=tuple(args))


def replace_value(steps: list[Step], rng: random.Random, interface: Interface) -> dict | None:
    """Give one argument of one request an exceptional value (the module doc)."""
    candidates = [i for i, s in enumerate(steps) if s.op == "send" and interface.services[s.service].args]
    if not candidates:
        return None
    i = rng.choice(candidates)
    old = steps[i]
    arg = rng.choice(list(interface.services[old.service].args.values()))
    kind, word = rng.choice(exceptional_values(arg))
    steps[i] = with_value(old, arg.name, word)
    return {"op": "replace_value", "line": old.line or None, "step": step_text(old), "argument": arg.name,
            "class": kind, "value": word}


def cases(arg: Argument, narrowed: Domain | None = None) -> list[tuple[str, str | None, bool]]:
    """(class, word, breaks) of each exceptional value of `arg`: against its own domain, every one
    (`breaks`: outside it); with a `narrowed` domain, those legal at rest, of both domains (`breaks`:
    outside the narrowed one). The cases the targeted and focused strategies aim at."""
    if narrowed is None:
        return [(kind, word, violation(arg, word) is not None) for kind, word in exceptional_values(arg)]
    return [(kind, word, violation(arg, word, narrowed) is not None)
            for kind, word in exceptional_values(arg) + exceptional_values(arg, narrowed)
            if violation(arg, word) is None]


def falsifying_request(request: Step, service: Service, rng: random.Random,
                       narrowed: dict[str, Domain] | None = None) -> tuple[Step, str] | None:
    """`request` (legal values) with one argument made illegal: outside its interface domain, or
    with `narrowed`, inside it but outside the narrowed domain; and what was done. None when no
    argument can be (a service without arguments, bounds that leave nothing between them).
    For the targeted strategies: a request that makes a value-domain property's C false."""
    options = [(arg.name, kind, word) for arg in service.args.values() if narrowed is None or arg.name in narrowed
               for kind, word, breaks in cases(arg, None if narrowed is None else narrowed[arg.name]) if breaks]
    if not options:
        return None
    name, kind, word = rng.choice(options)
    return with_value(request, name, word), f"{name} {kind}" + (" of the narrowed domain" if narrowed else "")
