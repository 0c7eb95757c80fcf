"""The interface description and the properties, read from TOML data files (DESIGN §2-§3)."""
from __future__ import annotations

import tomllib
from dataclasses import dataclass, field
from pathlib import Path

from harness.errors import InputFileError
from harness.files import decode
from harness.target.property_types import REPLY_CODES, property_types

SERVICE_KINDS = ("init", "control", "exec")
REPLY_CLASSES = ("T", "Z", "R")


@dataclass(frozen=True)
class Argument:
    name: str
    type: str  # "float" or "str"
    min: float | None = None
    max: float | None = None
    choices: tuple[str, ...] = ()


@dataclass(frozen=True)
class Service:
    module: str
    name: str
    kind: str
    args: dict[str, Argument] = field(default_factory=dict)
    until_stopped: bool = False  # an activity that never ends by itself (documented black-box fact)

    @property
    def qualified(self) -> str:
        return f"{self.module}.{self.name}"

    def typed(self, raw: dict[str, str]) -> dict:
        """A request's argument values as JSON types: numbers for float arguments."""
        return {k: float(v) if self.args[k].type == "float" else v for k, v in raw.items()}


@dataclass(frozen=True)
class Interface:
    path: str
    replies: dict[str, str]  # reply code -> class T/Z/R
    services: dict[str, Service]  # "module.Service" -> Service
    posters: dict[str, str]  # module -> poster name

    @property
    def until_stopped(self) -> list[str]:
        """The activities that end only when a request stops them."""
        return [name for name, s in self.services.items() if s.until_stopped]

    def of_kind(self, kind: str) -> list[str]:
        return [name for name, s in self.services.items() if s.kind == kind]

    @property
    def modules(self) -> list[str]:
        return list(dict.fromkeys(s.module for s in self.services.values()))

    def describe(self) -> dict:
        """What a SUT is told of the interface in the protocol's hello (DESIGN §8)."""
        modules: dict[str, dict[str, str]] = {}
        for s in self.services.values():
            modules.setdefault(s.module, {})[s.name] = s.kind
        return {"modules": modules, "replies": dict(self.replies)}

    def reply_codes(self) -> list[tuple[str, str, str, str]]:
        """Rows of the reply_codes table: every service may end with every catalogued code."""
        return [(s.module, s.name, code, cls)
                for s in self.services.values() for code, cls in self.replies.items()]


@dataclass(frozen=True)
class Property:
    id: str
    family: str
    type: str
    x: tuple[str, ...]
    y: tuple[str, ...] = ()
    q: tuple[str, ...] = ()
    r_p: str | None = None
    z_p: str | None = None


def read_toml(path: Path, missing: str = "file not found; pass an existing file") -> dict:
    """A TOML data file's contents; `missing` is the message for a file that is not there."""
    return parse_toml(path, read_bytes(path, missing))


def read_bytes(path: Path, missing: str) -> bytes:
    try:
        return Path(path).read_bytes()
    except FileNotFoundError:
        raise InputFileError(path, "", missing) from None


def parse_toml(path: Path, content: bytes) -> dict:
    """The TOML text `content` read from `path` (named in messages)."""
    text = decode(path, content)  # a file that is not UTF-8 is refused naming its line
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as e:
        raise InputFileError(path, "", f"not valid TOML: {e}") from None


# The keys each table of an interface description may hold: a typo (`agrs`) must not pass unseen.
INTERFACE_KEYS = {"the top level": ("replies", "modules"), "a module": ("doc", "poster", "services"),
                  "a service": ("kind", "args", "until_stopped", "doc"),
                  "a float argument": ("type", "min", "max", "doc"), "a str argument": ("type", "choices", "doc")}


def _known_keys(path, where, table: dict, what: str) -> None:
    unknown = sorted(set(table) - set(INTERFACE_KEYS[what]))
    if unknown:
        raise InputFileError(path, where, f"unknown key(s) {unknown}; {what} takes "
                             f"{', '.join(INTERFACE_KEYS[what])}")


def _argument(path, where, name, spec) -> Argument:
    if not isinstance(spec, dict) or spec.get("type") not in ("float", "str"):
        raise InputFileError(path, where, f"argument {name!r} has type {spec!r}; "
                             "use { type = \"float\", min = .., max = .. } or { type = \"str\", choices = [..] }")
    _known_keys(path, f"{where} args.{name}", spec, f"a {spec['type']} argument")
    if spec["type"] == "float":
        lo, hi = spec.get("min"), spec.get("max")
        if not isinstance(lo, (int, float)) or not isinstance(hi, (int, float)) or lo > hi:
            raise InputFileError(path, where, f"argument {name!r} needs numeric min <= max, got min={lo!r} max={hi!r}")
        return Argument(name, "float", float(lo), float(hi))
    choices = spec.get("choices")
    if not choices or not all(isinstance(c, str) for c in choices):
        raise InputFileError(path, where, f"argument {name!r} needs a non-empty list of string choices, got {choices!r}")
    return Argument(name, "str", choices=tuple(choices))


def load_interface(path: str | Path) -> Interface:
    path = Path(path)
    data = read_toml(path)
    _known_keys(path, "top level", data, "the top level")
    replies = data.get("replies")
    if not isinstance(replies, dict) or not replies:
        raise InputFileError(path, "[replies]", "missing reply catalogue; add a [replies] table of code = \"T|Z|R\"")
    for code, cls in replies.items():
        if cls not in REPLY_CLASSES:
            raise InputFileError(path, f"[replies] {code}", f"class {cls!r} is not one of T, Z, R")
    if replies.get("ok") != "T":
        given = f", not ok = {replies['ok']!r}" if "ok" in replies else ""
        raise InputFileError(path, "[replies]", f"the catalogue must contain ok = \"T\"{given}")
    modules = data.get("modules")
    if not isinstance(modules, dict) or not modules:
        raise InputFileError(path, "[modules]", "no modules declared; add [modules.NAME] tables")
    services, posters = {}, {}
    for module, mspec in modules.items():
        _known_keys(path, f"[modules.{module}]", mspec, "a module")
        if mspec.get("poster"):
            posters[module] = mspec["poster"]
        for name, sspec in (mspec.get("services") or {}).items():
            where = f"[modules.{module}] services.{name}"
            kind = sspec.get("kind") if isinstance(sspec, dict) else None
            if kind not in SERVICE_KINDS:
                raise InputFileError(path, where, f"kind {kind!r} is not one of {', '.join(SERVICE_KINDS)}")
            _known_keys(path, where, sspec, "a service")
            args = {a: _argument(path, where, a, spec) for a, spec in (sspec.get("args") or {}).items()}
            until_stopped = sspec.get("until_stopped", False)
            if until_stopped not in (True, False) or until_stopped and kind != "exec":
                raise InputFileError(path, where, f"until_stopped = {until_stopped!r}; it is true or false, "
                                     "and only an exec service may run until stopped")
            services[f"{module}.{name}"] = Service(module, name, kind, args, until_stopped)
        if not any(s.module == module for s in services.values()):
            raise InputFileError(path, f"[modules.{module}]", "module declares no services")
    return Interface(str(path), dict(replies), services, posters)


def _names(path, where, value, key, interface: Interface) -> tuple[str, ...]:
    if not isinstance(value, list) or not value or not all(isinstance(v, str) for v in value):
        raise InputFileError(path, where, f"{key} = {value!r}; give a non-empty list of \"module.Service\"")
    for v in value:
        if v not in interface.services:
            raise InputFileError(path, where, f"{key} names {v!r}, which the interface "
                                 f"{interface.path} does not declare")
    return tuple(value)


def load_properties(path: str | Path, interface: Interface) -> list[Property]:
    path = Path(path)
    entries = read_toml(path).get("property")
    if not isinstance(entries, list) or not entries:
        raise InputFileError(path, "", "no properties; add [[property]] entries")
    props, seen, types = [], set(), property_types()
    for n, e in enumerate(entries, 1):
        where = f"property #{n} ({e.get('id', '?')})"
        if not isinstance(e.get("id"), str) or not e["id"]:
            raise InputFileError(path, where, f"id = {e.get('id')!r}; every property needs a string id")
        if e["id"] in seen:
            raise InputFileError(path, where, f"id {e['id']!r} is used twice; ids must be unique")
        seen.add(e["id"])
        if e.get("type") not in types:
            raise InputFileError(path, where, f"type {e.get('type')!r} is not one of {', '.join(types)} "
                                 "(the templates of sql/oracles/)")
        if not isinstance(e.get("family"), str) or not e["family"]:
            raise InputFileError(path, where, f"family = {e.get('family')!r}; give a family name such as \"PEX\"")
        needed = types[e["type"]]
        unknown = set(e) - {"id", "family", "type", *needed}
        if unknown:
            raise InputFileError(path, where, f"key(s) {sorted(unknown)} do not apply to type {e['type']}; "
                                 f"it takes {', '.join(needed)}")
        fields = {}
        for key in needed:
            if key not in e:
                raise InputFileError(path, where, f"type {e['type']} needs {key!r}, which is missing")
            if key in REPLY_CODES:
                expected = REPLY_CODES[key]
                if interface.replies.get(e[key]) != expected:
                    raise InputFileError(path, where, f"{key} = {e[key]!r} is not a class-{expected} reply code "
                                         f"of the interface {interface.path}")
                fields[key] = e[key]
            else:
                fields[key] = _names(path, where, e[key], key, interface)
        props.append(Property(id=e["id"], family=e["family"], type=e["type"], **fields))
    return props
