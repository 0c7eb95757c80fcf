"""A simulated layer's own knowledge, read from its mission folder's layer.toml.

What the implementation enforces (protections), which reply code each answers with, the defects
that can be injected, and the named variants (protections + defects). This is the implementation's
view, kept apart from the tester's properties.toml: the layer never reads properties.

Protection kinds (each with its `reply` code):
- requires_init: an exec request of a module whose init has not ended ok is rejected.
- requires: `after` maps a service to those that must all have ended ok before it; else rejected.
- rejects_while: `while` maps a service to those whose running activity makes it rejected.
- interrupts: `by` maps a running service to the requests that interrupt it; `stop = true`: the
  layer's stop service interrupts every other activity of its module.
- excludes: `pairs` of services that never run together; an accepted request interrupts the
  running other one (priority to the latest request).
- checks_args: a request (of any kind) with an argument outside its interface domain is rejected
  when the way it breaks it is among `checks` (harness/target/domains.py VIOLATIONS: missing, type,
  nan, range, choices, pattern); `reply` defaults to [layer] invalid_args. An unchecked value
  reaches the module as read (a word that is no number as 0, a missing number as 0).
- narrows_while: `while` maps a service to those whose running activity narrows its arguments'
  domain to `domain` (argument -> min, max, choices, pattern); `reply` defaults to invalid_args.

Defect kinds:
- interrupts_on_init: every init request interrupts all running activities of its module (`reply`).
- deadlock_on_start: an interruption by `protection` that reaches an activity still in its start
  phase deadlocks that activity's module (no reply, no pong).
- leak_during_init: exec requests arriving while the module's init runs pass `protection`.
"""
from __future__ import annotations

import functools
import importlib
from dataclasses import dataclass, field
from pathlib import Path

from harness import current_modules
from harness.errors import InputFileError, UntimelyError
from harness.files import read_toml
from harness.schema import cut, dotted, validated, where
from harness.target.domains import Domain, narrowing
from harness.target.layer_file import CHECKING, DEFECT_KINDS, DefectTable, LayerFile, ProtectionTable
from harness.target.interface import Interface

@dataclass(frozen=True)
class Protection:
    name: str
    kind: str
    reply: str
    services: dict[str, frozenset[str]] = field(default_factory=dict)  # after / while / interrupted by
    stop: bool = False
    checks: tuple[str, ...] = ()  # checks_args: the violations it detects
    domain: dict = field(default_factory=dict)  # narrows_while: argument -> its Bounds table

    def names(self) -> set[str]:
        return set(self.services) | {s for group in self.services.values() for s in group}


@dataclass(frozen=True)
class Defect:
    name: str
    kind: str
    reply: str | None = None
    protection: str | None = None


@dataclass(frozen=True)
class Variant:
    name: str
    protections: tuple[Protection, ...]  # in the description's order: the order checks are made
    defects: tuple[Defect, ...]
    doc: str

    def defect(self, kind: str, protection: str | None = None) -> Defect | None:
        return next((d for d in self.defects if d.kind == kind and d.protection == protection), None)

    def __repr__(self) -> str:
        return (f"<Variant {self.name} protections={','.join(p.name for p in self.protections) or '-'} "
                f"defects={','.join(sorted(d.name for d in self.defects)) or '-'}>")


@dataclass(frozen=True)
class Timing:
    start_s: float
    run_s: float | None  # None: runs until an interruption ends it


@dataclass(frozen=True)
class LayerDescription:
    path: Path
    behaviour: str | None  # a Python module building the modules; None: modules timed from `timing`
    slots: int
    invalid_args: str  # the reply to arguments outside their domain
    no_slot: str
    stop: str | None  # the service that stops its module's other activities
    default_suts: tuple[str, ...]
    timing: dict[str, Timing]  # by "module.Service" or "Service"
    protections: dict[str, Protection]
    defects: dict[str, Defect]
    variants: dict[str, Variant]
    behaviour_at: str = ""  # the line of `behaviour` in the file, for its messages

    def behaviour_module(self):
        """The behaviour module, once it is known to import and to provide build(); None without one.
        Imported when a layer is built or a campaign checked, not when the file is read (the CLI reads
        it for its help, and the behaviour's own imports, e.g. pymunk, take a while)."""
        return _behaviour(self.path, self.behaviour_at, self.behaviour) if self.behaviour else None

    def variant(self, name: str) -> Variant:
        if name not in self.variants:
            raise UntimelyError(f"unknown variant {name!r}; choose one of {', '.join(self.variants)} "
                                f"(the variants of {self.path})")
        return self.variants[name]

    def timing_of(self, qualified: str) -> Timing | None:
        return self.timing.get(qualified) or self.timing.get(qualified.split(".", 1)[1])

    def check(self, interface: Interface) -> None:
        """Every code and service it names is the interface's."""
        codes = [self.invalid_args, self.no_slot] + [p.reply for p in self.protections.values()] \
            + [d.reply for d in self.defects.values() if d.reply]
        for code in codes:
            if code not in interface.replies:
                raise InputFileError(self.path, "", f"reply code {code!r} is not in the catalogue of the "
                                     f"interface {interface.path}; add it there or use one of "
                                     f"{', '.join(interface.replies)}")
        for p in self.protections.values():
            unknown = sorted(p.names() - set(interface.services))
            if unknown:
                raise InputFileError(self.path, f"[protections.{p.name}]", f"names {unknown[0]!r}, which the "
                                     f"interface {interface.path} does not declare")
            for service in p.services if p.kind == "narrows_while" else ():
                self.narrowed(p, interface.services[service].args)

    def narrowed(self, protection: Protection, arguments: dict) -> dict[str, Domain]:
        """A narrows_while protection's domain over a service's `arguments` (refused if it names others)."""
        try:
            return narrowing(arguments, protection.domain)
        except ValueError as e:
            raise InputFileError(self.path, f"[protections.{protection.name}]", str(e)) from None


def _protection(path, text, name: str, spec: ProtectionTable, invalid_args: str) -> Protection:
    services: dict[str, set[str]] = {}
    for table in (spec.after, spec.while_, spec.by):
        for service, others in table.items():
            services.setdefault(service, set()).update(others)
    for a, b in spec.pairs:
        services.setdefault(a, set()).add(b)
        services.setdefault(b, set()).add(a)
    if spec.reply is None and spec.kind not in CHECKING:
        raise InputFileError(path, where(text, ("protections", name)),
                             f"protections.{name}: reply is missing; give the reply code it answers with")
    return Protection(name, spec.kind, spec.reply or invalid_args, {k: frozenset(v) for k, v in services.items()},
                      spec.stop, tuple(spec.checks) if spec.kind == "checks_args" else (),
                      spec.domain if spec.kind == "narrows_while" else {})


def _defect(path, text, name, spec: DefectTable, protections) -> Defect:
    needed = DEFECT_KINDS[spec.kind]
    value = getattr(spec, needed)
    if needed == "reply" and value is None:
        raise InputFileError(path, where(text, ("defects", name)),
                             f"defects.{name}: reply is missing; give the reply code it answers with")
    if needed == "protection" and value not in protections:
        raise InputFileError(path, where(text, ("defects", name, "protection")),
                             f"defects.{name}: protection = {cut(value)}; name one of {', '.join(protections)}")
    return Defect(name, spec.kind, **{needed: value})


def _picked(path, text, keys: tuple, names, known: dict) -> tuple:
    """The entries of `known` that the list `names` picks."""
    for n in names:
        if n not in known:
            raise InputFileError(path, where(text, keys), f"{dotted(keys)} names {cut(n)}; use one of "
                                 f"{', '.join(known) or '(none declared)'}")
    return tuple(known[n] for n in names)


@functools.cache
def _behaviour(path: Path, at: str, name: str):
    try:
        module = importlib.import_module(current_modules(name))  # a name from before harness/sut/ too
    except Exception as e:  # any failure to import is the file's error, named with its cause
        raise InputFileError(path, at, f"behaviour = {cut(name)} cannot be imported ({e}); name an importable "
                             "Python module") from None
    if not callable(getattr(module, "build", None)):
        raise InputFileError(path, at, f"behaviour = {cut(name)} has no build(env, world_file) function; name a "
                             "module that builds the layer's modules")
    return module


@functools.cache
def _load(path: Path, _stamp: tuple) -> LayerDescription:
    data, text = read_toml(path, f"file not found; a simulated target describes its layer in {path.name}")
    spec = validated(LayerFile, data, path, text)
    protections = {n: _protection(path, text, n, s, spec.layer.invalid_args) for n, s in spec.protections.items()}
    defects = {n: _defect(path, text, n, s, protections) for n, s in spec.defects.items()}
    variants = {}
    for name, v in spec.variants.items():
        enforced = {p.name for p in _picked(path, text, ("variants", name, "protections"), v.protections, protections)}
        variants[name] = Variant(name, tuple(p for p in protections.values() if p.name in enforced),  # file order
                                 _picked(path, text, ("variants", name, "defects"), v.defects, defects), v.doc)
    layer = spec.layer
    default = _picked(path, text, ("layer", "default_suts"), layer.default_suts or list(variants), variants)
    timing = {n: Timing(t.start_s, None if t.run_s == "forever" else t.run_s) for n, t in spec.timing.items()}
    return LayerDescription(path, layer.behaviour, layer.slots, layer.invalid_args, layer.no_slot, layer.stop,
                            tuple(v.name for v in default), timing, protections, defects, variants,
                            where(text, ("layer", "behaviour")))


def load_layer_file(path: Path) -> LayerDescription:
    """The layer description in the file `path` (a mission folder's, harness.target.mission.load_layer),
    read once per file version."""
    path = Path(path).resolve()
    try:
        stat = path.stat()
        stamp = (stat.st_mtime_ns, stat.st_size)
    except FileNotFoundError:
        stamp = ()
    return _load(path, stamp)
