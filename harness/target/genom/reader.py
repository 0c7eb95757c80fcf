"""What a GenoM3 description (`.gen`) declares: its components and interfaces, their services
(attribute, function, activity), each service's clauses (interrupts, before, after, validate,
throw) and the exceptions; `provides` brings an interface's services and exceptions into a
component, and so does genom3's standard interface `genom` (standard.gen) for every component.

The text is preprocessed (preprocess.py), then parsed with the grammar dotgen.lark (lark, LALR):
a declaration the grammar cannot read is refused with its file, line and what was expected.
"""
from __future__ import annotations

import functools
from dataclasses import dataclass, field
from pathlib import Path

from lark import Lark, Token, Tree
from lark.exceptions import UnexpectedInput

from harness.errors import InputFileError
from harness.target.genom.params import CodelParam, Param, codel_param, service_param
from harness.target.genom.preprocess import Origin, Source, preprocess

HERE = Path(__file__).resolve().parent
STANDARD = HERE / "standard.gen"
CLAUSES = ("interrupts", "before", "after", "throws")


@dataclass
class GenomService:
    name: str
    kind: str  # attribute | function | activity
    where: Origin
    clauses: dict[str, list[str]] = field(default_factory=dict)  # interrupts/before/after/throws -> names
    lines: dict[str, Origin] = field(default_factory=dict)  # clause -> where it is written
    validate: str | None = None  # the validate codel's name
    params: tuple[Param, ...] = ()  # the service's parameters
    checks: tuple[CodelParam, ...] = ()  # the validate codel's parameters
    codels: int = 0  # codels besides validate
    scope: str = ""  # the component or interface that declares it

    def listed(self, clause: str) -> list[str]:
        return self.clauses.get(clause, [])


@dataclass
class GenomScope:
    """A component or an interface."""
    name: str
    where: Origin
    interface: bool
    services: dict[str, GenomService] = field(default_factory=dict)
    exceptions: dict[str, Origin] = field(default_factory=dict)
    provides: list[tuple[str, Origin]] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)


@functools.cache
def _parser() -> Lark:
    return Lark((HERE / "dotgen.lark").read_text(), parser="lalr", propagate_positions=True)


def _names(tree: Tree) -> list[str]:
    """A `names` list, each scoped name as written without its leading `::` (genom::x stays)."""
    return ["::".join(str(t) for t in scoped.children) for scoped in tree.children]


def _service(tree: Tree, source: Source, scope: str) -> GenomService:
    kind, name = tree.children[0], tree.children[1]
    service = GenomService(str(name), str(kind), source.origins[name.line - 1], scope=scope)
    service.params = tuple(service_param(c) for c in tree.children[2:] if isinstance(c, Tree) and c.data == "parameter")
    clauses = next((c for c in tree.children[2:] if isinstance(c, Tree) and c.data == "clauses"), None)
    for clause in clauses.children if clauses else []:
        where = source.origins[clause.meta.line - 1]
        if clause.data in CLAUSES:
            listed = next(c for c in clause.children if isinstance(c, Tree) and c.data == "names")
            service.clauses.setdefault(clause.data, []).extend(_names(listed))
            service.lines.setdefault(clause.data, where)
        elif clause.data == "validate":
            service.validate, service.lines["validate"] = str(clause.children[0]), where
            service.checks = tuple(codel_param(c) for c in clause.children[1:] if c is not None)
        elif clause.data == "codel":
            service.codels += 1
    return service


def _scope(tree: Tree, source: Source) -> GenomScope:
    name = tree.children[0]
    scope = GenomScope(str(name), source.origins[name.line - 1], tree.data == "interface")
    body = tree.children[1] if len(tree.children) > 1 else None
    for item in body.children if body is not None else []:
        where = source.origins[item.meta.line - 1]
        if item.data == "service":
            service = _service(item, source, scope.name)
            if service.name in scope.services:
                raise InputFileError(where.file, where.line, f"service {service.name} is declared twice in "
                                     f"{scope.name} (first at {scope.services[service.name].where}); keep one")
            scope.services[service.name] = service
        elif item.data == "exception":
            scope.exceptions.update({str(m.children[0]): where for m in item.children})
        elif item.data == "provides":
            scope.provides += [(n, where) for n in _names(item.children[0])]
    return scope


MAX_EXPECTED = 8  # past this, the list says less than the line itself
WORDS = {"NAME": "a name", "WORD": "a word or number", "STRING": "a string", "CHAR": "a character",
         "OPERATOR": "an operator", "KIND": "attribute, function or activity", "DIRECTION": "in, out or inout"}


def _described(terminals) -> str:
    """The terminals the parser expected, as a user writes them: ',' rather than COMMA."""
    said = []
    for name in sorted(terminals)[:MAX_EXPECTED]:
        if name == "$END":  # lark's own, no terminal of the grammar
            said.append("the end of the file")
            continue
        pattern = _parser().get_terminal(name).pattern
        said.append(repr(pattern.value) if pattern.type == "str" else WORDS.get(name, name.lower()))
    return " or ".join(said) or "something else"


def _parse(source: Source, path: Path) -> list[GenomScope]:
    try:
        tree = _parser().parse(source.text)
    except UnexpectedInput as e:
        raise _unreadable(e, source, path) from None
    return [_scope(t, source) for t in tree.children if isinstance(t, Tree) and t.data in ("component", "interface")]


def _unreadable(e: UnexpectedInput, source: Source, path: Path) -> InputFileError:
    """The refusal of what the grammar cannot read: where, what is written there, what it expected."""
    lines = source.text.split("\n")
    if getattr(getattr(e, "token", None), "type", None) == "$END" or not e.line or e.line < 1:
        last = max((n for n, text in enumerate(lines) if text.strip()), default=0)
        where = source.origins[last] if source.origins else Origin(str(path), 0)
        return InputFileError(where.file, where.line, "the file ends inside a declaration: a '}' or a ';' is "
                              "missing; close every brace and end every declaration with ';'")
    where = source.origins[e.line - 1]
    expected = _described(getattr(e, "expected", None) or getattr(e, "allowed", None) or [])
    return InputFileError(where.file, where.line, f"cannot read {lines[e.line - 1].strip()[:80]!r} at column "
                          f"{e.column}: the dotgen grammar expects {expected} there; write the declaration as "
                          "genom3's grammar says (genom3 must accept the file)")


def read_scopes(path: Path, includes: list[Path]) -> tuple[list[GenomScope], list[GenomScope], Source]:
    """The components and the interfaces (genom3's standard one included) of a .gen file."""
    source = preprocess(path, includes)
    scopes = _parse(source, path)
    standard = _parse(preprocess(STANDARD, []), STANDARD)
    components, interfaces = [s for s in scopes if not s.interface], standard + [s for s in scopes if s.interface]
    seen: dict[str, Origin] = {}
    for component in components:
        if component.name in seen:
            where = component.where
            raise InputFileError(where.file, where.line, f"component {component.name} is declared twice (first at "
                                 f"{seen[component.name]}); a .gen file declares each component once")
        seen[component.name] = component.where
    if not components:
        declared = f" (it declares the interfaces {', '.join(s.name for s in scopes)})" if scopes else ""
        raise InputFileError(path, "", f"no `component NAME {{ ... }};` found{declared}; give the .gen file of a "
                             "GenoM3 component")
    return components, interfaces, source


def provided(component: GenomScope, interfaces: list[GenomScope], pragmas: list[tuple[Origin, str]]) -> None:
    """Bring into the component the services and exceptions of the interfaces it provides:
    `provides` clauses, `#pragma provides`, and genom3's standard interface `genom`."""
    named = {i.name: i for i in interfaces}
    wanted = [("genom", STANDARD_ORIGIN)] + component.provides
    wanted += [(words.split()[1], where) for where, words in pragmas if words.split()[:1] == ["provides"]
               and len(words.split()) > 1]
    for name, where in wanted:
        interface = named.get(name.split("::")[-1])
        if interface is None:
            raise InputFileError(where.file, where.line, f"{component.name} provides {name!r}, an interface that no "
                                 "file read declares; #include the .gen file that declares it (with --include DIR)")
        for exception, at in interface.exceptions.items():
            component.exceptions.setdefault(exception, at)
        for service in interface.services.values():
            if service.name in component.services:
                component.notes.append(f"{component.name}.{service.name} ({component.services[service.name].where}) "
                                       f"replaces the one interface {name} provides ({service.where})")
            else:
                component.services[service.name] = service


STANDARD_ORIGIN = Origin(str(STANDARD), 0)
