"""The parameters of a service and of its validate codel, as dotgen.lark parses them.

A service parameter (grammar rules 30 and 32) is a direction, an IDL type and a name, or for an
attribute an ids member (`in battery.min`, named `min`, whose type the ids declares); then an
optional default value and doc string (rule 47). The bench carries a value as a float or a text
(harness/target/domains.py): a parameter maps to one when its type is a number or a string (for an
attribute, when its default is one); a struct, an array, a sequence or a named type does not.

A codel parameter (rule 40) names a service parameter (`local`), an ids member (`ids`), a port or a
remote; without a source genom3 looks the name up among all four and refuses an ambiguous one, so
an unqualified name equal to a service parameter's is that parameter."""
from __future__ import annotations

import json
from dataclasses import dataclass

from lark import Token, Tree

NUMBERS = {"float", "double", "short", "long", "unsigned", "octet", "int8_t", "uint8_t", "int16_t", "uint16_t",
           "int32_t", "uint32_t", "int64_t", "uint64_t"}


@dataclass(frozen=True)
class Param:
    name: str
    direction: str  # in | out | inout
    type: str | None  # "float" or "str" when the bench can carry it, else None
    default: str | None  # the default value as one word of a mission script, None if it has none
    doc: str = ""
    written: str = ""  # the declaration as written, for messages


@dataclass(frozen=True)
class CodelParam:
    source: str | None  # ids | local | port | remote, None when not written
    direction: str
    name: str  # the first name of the path it reads (`rate` of `local in rate.imu`)

    def local(self, params: tuple[Param, ...]) -> bool:
        """Whether it names one of the service's parameters."""
        return self.source == "local" or (self.source is None and any(p.name == self.name for p in params))


def _text(token: Token) -> str:
    """A string literal's text (C's escapes are JSON's but for a few rare ones, kept as written)."""
    try:
        return json.loads(str(token))
    except ValueError:
        return str(token)[1:-1]


def _words(children) -> list[str]:
    return [str(c) for c in children if isinstance(c, Token) and c.type == "WORD"]


def _value(tree: Tree | None) -> tuple[str | None, str | None]:
    """The default's type and word: ("str", text) for a string, ("float", word) for a number, else Nones."""
    if tree is None or any(isinstance(c, Tree) for c in tree.children) or not tree.children:
        return None, None  # no value, or a compound one ({...}, an expression in brackets)
    tokens = tree.children
    if len(tokens) == 1 and tokens[0].type == "STRING":
        return "str", _text(tokens[0])
    text = "".join(str(t) for t in tokens)
    try:
        float(text)
    except ValueError:
        return None, None  # a constant expression (2*M_PI, an enum value): not a plain number
    return "float", text


def service_param(tree: Tree) -> Param:
    direction, rest = str(tree.children[0]), tree.children[1:]
    default = next((c for c in rest if isinstance(c, Tree) and c.data == "initializer"), None)
    strings = next((c for c in rest if isinstance(c, Tree) and c.data == "strings"), None)
    declared = [c for c in rest if c is not None and c is not default and c is not strings]
    words = _words(declared)
    array = bool(declared) and isinstance(declared[-1], Tree) and declared[-1].data == "blob_in"
    given, value = _value(default)
    if len(words) > 1:  # a function's or an activity's parameter: its IDL type is written
        kind = None if array else "str" if words[0] == "string" else "float" if set(words[:-1]) <= NUMBERS else None
    else:  # an attribute's: an ids member, whose default tells its type
        kind = given
    doc = " ".join(_text(s) for s in strings.children) if strings is not None else ""
    name = words[-1].rsplit(".", 1)[-1] if words else ""
    return Param(name, direction, kind, value if given == kind else None, doc, " ".join([direction, *words]))


def codel_param(tree: Tree) -> CodelParam:
    first = tree.children[0]
    source = str(first) if isinstance(first, Token) and first.type == "SOURCE" else None
    direction = str(tree.children[1 if source else 0])
    words = _words(tree.children[2 if source else 1:])
    return CodelParam(source, direction, words[0].split(".")[0] if words else "")
