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

Defect kinds:
- interrupts_on_init: every init request interrupts all running activities of its module (`reply`).
- deadlock_on_start: an interruption by `protection` that reaches an activity still in its start
  phase deadlocks that activity's module (no reply, no pong).
- leak_during_init: exec requests arriving while the module's init runs pass `protection`.
"""
from __future__ import annotations

import functools
from dataclasses import dataclass, field
from pathlib import Path

from harness.errors import InputFileError, UntimelyError
from harness.target.interface import Interface, read_toml

LAYER_FILE = "layer.toml"
REJECTING = ("requires_init", "requires", "rejects_while")
INTERRUPTING = ("interrupts", "excludes")
DEFECT_KINDS = {"interrupts_on_init": "reply", "deadlock_on_start": "protection", "leak_during_init": "protection"}
LAYER_KEYS = {"behaviour", "slots", "invalid_args", "no_slot", "stop", "default_suts", "doc"}


@dataclass(frozen=True)
class Protection:
    name: str
    kind: str
    reply: str
    services: dict[str, frozenset[str]] = field(default_factory=dict)  # after / while / interrupted by
    stop: bool = False

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


def _strings(path, where, key, value) -> tuple[str, ...]:
    if not isinstance(value, list) or not all(isinstance(v, str) for v in value):
        raise InputFileError(path, where, f"{key} = {value!r}; give a list of names")
    return tuple(value)


def _code(path, where, spec, key="reply") -> str:
    if not isinstance(spec.get(key), str):
        raise InputFileError(path, where, f"{key} = {spec.get(key)!r}; give the reply code it answers with")
    return spec[key]


def _protection(path, name, spec) -> Protection:
    where = f"[protections.{name}]"
    kind = spec.get("kind")
    if kind not in REJECTING + INTERRUPTING:
        raise InputFileError(path, where, f"kind = {kind!r}; use one of {', '.join(REJECTING + INTERRUPTING)}")
    table = {"requires": "after", "rejects_while": "while", "interrupts": "by"}.get(kind)
    services: dict[str, set[str]] = {}
    if table:
        for service, others in spec.get(table, {}).items():
            services[service] = set(_strings(path, where, f"{table}.{service!r}", others))
    if kind == "excludes":
        for pair in spec.get("pairs", []):
            if not isinstance(pair, list) or len(pair) != 2:
                raise InputFileError(path, where,
                                     f"pairs entry {pair!r}; give [\"module.Service\", \"module.Service\"]")
            a, b = _strings(path, where, "pairs entry", pair)
            services.setdefault(a, set()).add(b)
            services.setdefault(b, set()).add(a)
    return Protection(name, kind, _code(path, where, spec), {k: frozenset(v) for k, v in services.items()},
                      spec.get("stop", False) is True)


def _defect(path, name, spec, protections) -> Defect:
    where = f"[defects.{name}]"
    kind = spec.get("kind")
    if kind not in DEFECT_KINDS:
        raise InputFileError(path, where, f"kind = {kind!r}; use one of {', '.join(DEFECT_KINDS)}")
    if DEFECT_KINDS[kind] == "reply":
        return Defect(name, kind, reply=_code(path, where, spec))
    if spec.get("protection") not in protections:
        raise InputFileError(path, where, f"protection = {spec.get('protection')!r}; "
                             f"name one of {', '.join(protections)}")
    return Defect(name, kind, protection=spec["protection"])


def _timing(path, name, spec) -> Timing:
    run_s = spec.get("run_s")
    if not isinstance(spec.get("start_s", 0.0), (int, float)) or not (
            run_s == "forever" or isinstance(run_s, (int, float))):
        raise InputFileError(path, f"[timing] {name}",
                             f"{spec!r}; give {{ start_s = SECONDS, run_s = SECONDS or \"forever\" }}")
    return Timing(float(spec.get("start_s", 0.0)), None if run_s == "forever" else float(run_s))


def _picked(path, where, key, names, known: dict) -> tuple:
    """The entries of `known` that the list `names` picks."""
    for n in _strings(path, where, key, names):
        if n not in known:
            raise InputFileError(path, where, f"{key} names {n!r}; use one of {', '.join(known) or '(none declared)'}")
    return tuple(known[n] for n in names)


@functools.cache
def _load(path: Path, _stamp: tuple) -> LayerDescription:
    data = read_toml(path, f"file not found; a simulated target describes its layer in {LAYER_FILE}")
    layer = data.get("layer", {})
    unknown = set(layer) - LAYER_KEYS
    if unknown:
        raise InputFileError(path, "[layer]",
                             f"unknown key(s) {sorted(unknown)}; known: {', '.join(sorted(LAYER_KEYS))}")
    protections = {n: _protection(path, n, s) for n, s in data.get("protections", {}).items()}
    defects = {n: _defect(path, n, s, protections) for n, s in data.get("defects", {}).items()}
    variants = {}
    for name, spec in data.get("variants", {}).items():
        where = f"[variants.{name}]"
        enforced = {p.name for p in _picked(path, where, "protections", spec.get("protections", []), protections)}
        variants[name] = Variant(name, tuple(p for p in protections.values() if p.name in enforced),  # file order
                                 _picked(path, where, "defects", spec.get("defects", []), defects),
                                 spec.get("doc", ""))
    if not variants:
        raise InputFileError(path, "[variants]", "no variants; add [variants.NAME] tables (protections, defects, doc)")
    default = _picked(path, "[layer]", "default_suts", layer.get("default_suts", list(variants)), variants)
    if not isinstance(layer.get("slots", 3), int) or layer.get("slots", 3) < 1:
        raise InputFileError(path, "[layer]", f"slots = {layer['slots']!r}; give a whole number of activities >= 1")
    return LayerDescription(
        path, layer.get("behaviour"), layer.get("slots", 3), _code(path, "[layer]", layer, "invalid_args"),
        _code(path, "[layer]", layer, "no_slot"), layer.get("stop"), tuple(v.name for v in default),
        {n: _timing(path, n, s) for n, s in data.get("timing", {}).items()}, protections, defects, variants)


def load_layer(folder: Path) -> LayerDescription:
    """The layer description of a mission folder, read once per file version."""
    path = (Path(folder) / LAYER_FILE).resolve()
    try:
        stat = path.stat()
        stamp = (stat.st_mtime_ns, stat.st_size)
    except FileNotFoundError:
        stamp = ()
    return _load(path, stamp)
