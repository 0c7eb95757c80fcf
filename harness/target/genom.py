"""What a GenoM3 component description (`.gen`) states about the interface and its properties.

`untimely init DIR --from-genom FILE.gen` reads, for every `component NAME { ... };` of the file:
- its services: `attribute` and `function` are control services, `activity` an exec service, and
  the init service (the one named `init`, in any case) an init service;
- its `exception` declarations: reply codes of class T (an activity may end with one);
- `interrupt`/`interrupts` clauses (a list of services, or `all`): S interrupts x becomes the
  AIB-like EE property of x, whose dominators y are every service that interrupts it;
- `after` clauses: S after Q becomes the PRE-like PC property of S with q = Q;
- the init service: the PEX property of the component (every other exec service needs its `ok`).
It does not read types, ports, tasks or codels; what it could not derive is listed in `notes`.
"""
from __future__ import annotations

import re
from dataclasses import dataclass, field
from pathlib import Path

from harness.errors import InputFileError
from harness.files import read_text

KINDS = {"attribute": "control", "function": "control", "activity": "exec"}
IDENT = r"[A-Za-z_][A-Za-z0-9_]*"
COMMENTS = re.compile(r"//[^\n]*|/\*.*?\*/|#[^\n]*", re.S)
STRINGS = re.compile(r'"(?:[^"\\]|\\.)*"')
COMPONENT = re.compile(rf"\bcomponent\s+({IDENT})\s*\{{")
SERVICE = re.compile(rf"\b(attribute|function|activity)\s+({IDENT})\s*\(")
EXCEPTION = re.compile(r"\bexception\s+([^;]*);")
MEMBERS = re.compile(r"\{[^{}]*\}")  # an exception's members: `e_limits { double v; }`
CLAUSE = re.compile(r"\b(interrupts?|after)\s+([^;{}]*);")


@dataclass
class GenomService:
    name: str
    kind: str
    interrupts: list[str] = field(default_factory=list)  # names, or ["all"]
    after: list[str] = field(default_factory=list)
    line: int = 0


@dataclass
class GenomComponent:
    name: str
    services: dict[str, GenomService]
    exceptions: list[str]


def _blanked(text: str) -> str:
    """The text with comments and string literals blanked out, lines kept (for line numbers)."""
    def blank(match: re.Match) -> str:
        return re.sub(r"[^\n]", " ", match.group(0))
    return STRINGS.sub(blank, COMMENTS.sub(blank, text))


def _closing(text: str, opening: int, path: Path, what: str) -> int:
    """The index of the brace closing the one at `opening`."""
    depth = 0
    for i in range(opening, len(text)):
        depth += {"{": 1, "}": -1}.get(text[i], 0)
        if depth == 0:
            return i
    raise InputFileError(path, f"line {text.count(chr(10), 0, opening) + 1}", f"{what} has no closing brace; "
                         "check the braces of the .gen file (it must be accepted by genom3)")


def _names(listed: str) -> list[str]:
    return [n.strip() for n in listed.split(",") if n.strip()]


def _services(body: str, offset: int, text: str, path: Path) -> dict[str, GenomService]:
    services = {}
    for match in SERVICE.finditer(body):
        opening = body.find("{", match.end())
        semicolon = body.find(";", match.end())
        line = text.count("\n", 0, offset + match.start()) + 1
        kind = "init" if match.group(2).lower() == "init" else KINDS[match.group(1)]
        service = GenomService(match.group(2), kind, line=line)
        if opening != -1 and (semicolon == -1 or opening < semicolon):  # a service with clauses
            clauses = body[opening:_closing(body, opening, path, f"{match.group(1)} {match.group(2)}")]
            for clause, listed in CLAUSE.findall(clauses):
                (service.after if clause == "after" else service.interrupts).extend(_names(listed))
        services[service.name] = service
    return services


def read_genom(path: str | Path) -> list[GenomComponent]:
    """The components a .gen file declares (refused, naming the file, when it declares none)."""
    path = Path(path)
    text = _blanked(read_text(path))
    components = []
    for match in COMPONENT.finditer(text):
        opening = match.end() - 1
        body = text[opening:_closing(text, opening, path, f"component {match.group(1)}")]
        exceptions = [n for listed in EXCEPTION.findall(MEMBERS.sub("", body)) for n in _names(listed)]
        components.append(GenomComponent(match.group(1), _services(body, opening, text, path), exceptions))
    if not components:
        raise InputFileError(path, "", "no `component NAME { ... };` found; give a GenoM3 component description")
    for component in components:
        if not component.services:
            raise InputFileError(path, f"component {component.name}", "declares no attribute, function or "
                                 "activity; the interface needs services")
    return components
