"""Argument domains (docs/targets.md): what values an interface declares legal for each argument,
how a value written in a mission script is carried as JSON, and which way a value breaks its domain.

An argument is `float` or `str`. Without more, its domain is any value of its type: any finite
number, any text. A float may narrow it with `min` and `max`, a str with `choices` and a `pattern`
(a regular expression the whole text must match); `required = false` lets a request omit it.

A script writes every value as one word. A float argument's word that reads as a finite number is
carried as a JSON number; `nan`, `inf` and `-inf` as the JSON strings "nan", "inf", "-inf" (JSON has
no such numbers); any other word as a JSON string, a value of the wrong type. A str argument's word
is carried as a JSON string, `""` standing for the empty text. So any value reaches the layer, which
is what must refuse it (a value-domain property checks that it does).

The tables that declare domains (an interface's arguments, a property's or a protection's
narrowed `domain`) are read by the models below, through the one schema layer (harness/schema.py).
"""
from __future__ import annotations

import math
import re
from dataclasses import dataclass

from typing import Literal

from pydantic import ConfigDict, Field, model_validator

from harness.schema import Strict

EMPTY_TEXT = '""'  # how a script writes the empty text
NON_FINITE = {"nan": math.nan, "inf": math.inf, "-inf": -math.inf}
# The ways a value breaks its domain, in the order they are told apart; a layer's `checks_args`
# protection lists those it detects (harness/target/layer_description.py).
VIOLATIONS = ("missing", "type", "nan", "range", "choices", "pattern")


@dataclass(frozen=True)
class Domain:
    """The legal values of one argument (None: no bound of that kind)."""
    min: float | None = None
    max: float | None = None
    choices: tuple[str, ...] = ()
    pattern: str | None = None

    def spec(self) -> dict:
        """The bounds it sets, for rendering into SQL."""
        return {k: v for k, v in (("min", self.min), ("max", self.max), ("choices", list(self.choices)),
                                  ("pattern", self.pattern)) if v not in (None, [])}


@dataclass(frozen=True)
class Argument:
    name: str
    type: str  # "float" or "str"
    min: float | None = None
    max: float | None = None
    choices: tuple[str, ...] = ()
    pattern: str | None = None
    required: bool = True

    @property
    def domain(self) -> Domain:
        return Domain(self.min, self.max, self.choices, self.pattern)

    def describe(self) -> str:
        """Its domain in words, e.g. `float 0..20`, `str in velocity|idle`, `optional str matching [a-z]+`."""
        words = ["optional"] if not self.required else []
        words.append(self.type)
        if self.min is not None or self.max is not None:
            words.append(f"{'' if self.min is None else f'{self.min:g}'}..{'' if self.max is None else f'{self.max:g}'}")
        if self.choices:
            words.append("in " + "|".join(self.choices))
        if self.pattern is not None:
            words.append(f"matching {self.pattern}")
        return " ".join(words)

    def spec(self) -> dict:
        """Its type, whether it is required and its bounds, for rendering into SQL."""
        return {"type": self.type, "required": self.required, **self.domain.spec()}


def number(word: str) -> float | None:
    """The number a float argument's word stands for (nan and infinities included), else None."""
    if word.lower() in NON_FINITE:
        return NON_FINITE[word.lower()]
    try:
        value = float(word)
    except ValueError:
        return None
    return value if math.isfinite(value) else None  # 1e999: a word that overflows is no number


def carried(arg: Argument, word: str) -> float | str:
    """The JSON value a script's word is carried as (module doc)."""
    if arg.type == "str":
        return "" if word == EMPTY_TEXT else word
    value = number(word)
    if value is None:
        return word
    return value if math.isfinite(value) else word.lower()


def violation(arg: Argument, word: str | None, domain: Domain | None = None) -> str | None:
    """How the word (None: the argument is missing) breaks `domain` (default: the argument's own),
    one of VIOLATIONS; None when it is legal. A missing optional argument is legal."""
    domain = domain or arg.domain
    if word is None:
        return "missing" if arg.required else None
    if arg.type == "float":
        value = number(word)
        if value is None:
            return "type"
        if math.isnan(value):
            return "nan"
        low, high = domain.min if domain.min is not None else -math.inf, domain.max if domain.max is not None else math.inf
        return None if math.isfinite(value) and low <= value <= high else "range"
    text = carried(arg, word)
    if domain.choices and text not in domain.choices:
        return "choices"
    if domain.pattern is not None and not re.fullmatch(domain.pattern, text):
        return "pattern"
    return None


def _sound(table):
    """The table, or a ValueError for bounds that no value meets or a pattern that is no regular expression."""
    low, high, pattern = (getattr(table, k, None) for k in ("min", "max", "pattern"))
    if low is not None and high is not None and low > high:
        raise ValueError(f"needs min <= max, got min={low!r} max={high!r}")
    if pattern is not None:
        try:
            re.compile(pattern)
        except re.error as e:
            raise ValueError(f"pattern = {pattern!r} is not a regular expression ({e}); "
                             'write one such as "[a-z_]{1,32}"') from None
    return table


class Sound(Strict):
    """A table whose bounds some value meets and whose pattern is a regular expression."""

    @model_validator(mode="after")
    def _sound(self):
        return _sound(self)


class Bounds(Sound):
    """The bounds a table sets on an argument (each optional): min..max for a float, choices and a
    pattern for a str."""
    model_config = ConfigDict(title="a narrowed domain")
    min: float | None = Field(None, description="give a finite number, at most max")
    max: float | None = Field(None, description="give a finite number, at least min")
    choices: list[str] = Field(default_factory=list, description="give a list of string choices")
    pattern: str | None = Field(None, description='give a regular expression such as "[a-z_]{1,32}"')

    def domain(self) -> Domain:
        return Domain(self.min, self.max, tuple(self.choices), self.pattern)


class FloatArgumentFile(Sound):
    model_config = ConfigDict(title="a float argument")
    type: Literal["float"]
    min: float | None = Field(None, description="give a finite number, at most max")
    max: float | None = Field(None, description="give a finite number, at least min")
    required: bool = Field(True, description="give true or false")
    doc: str = ""


class StrArgumentFile(Sound):
    model_config = ConfigDict(title="a str argument")
    type: Literal["str"]
    choices: list[str] = Field(default_factory=list, description="give a list of string choices")
    pattern: str | None = Field(None, description='give a regular expression such as "[a-z_]{1,32}"')
    required: bool = Field(True, description="give true or false")
    doc: str = ""


ARGUMENT_HINT = ('give { type = "float", min = .., max = .. } or { type = "str", choices = [..], pattern = ".." } '
                 "(bounds optional; required = false for an optional argument)")


def argument(name: str, spec: FloatArgumentFile | StrArgumentFile) -> Argument:
    """The argument an interface declares, from its validated table."""
    if spec.type == "float":
        return Argument(name, "float", spec.min, spec.max, required=spec.required)
    return Argument(name, "str", choices=tuple(spec.choices), pattern=spec.pattern, required=spec.required)


def narrowing(arguments: dict[str, Argument], spec: dict[str, Bounds]) -> dict[str, Domain]:
    """A state-dependent domain (argument name -> bounds that hold besides the argument's own), or
    a ValueError naming an argument that none of the services takes or a bound not of its type."""
    for name, bounds in spec.items():
        if name not in arguments:
            raise ValueError(f"domain names argument {name!r}, which none of its services takes; "
                             f"they take {', '.join(arguments) or 'no arguments'}")
        misplaced = ({"choices", "pattern"} if arguments[name].type == "float" else {"min", "max"}) \
            & bounds.model_fields_set
        if misplaced:
            raise ValueError(f"domain.{name} sets {', '.join(sorted(misplaced))}, which do not apply to a "
                             f"{arguments[name].type} argument")
    return {name: bounds.domain() for name, bounds in spec.items()}
