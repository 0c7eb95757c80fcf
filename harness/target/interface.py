"""The interface description and the properties, read from TOML data files (docs/reference/interface.md and docs/reference/properties.md)."""
from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Annotated, Literal

from pydantic import ConfigDict, Field, model_validator

from harness.errors import InputFileError
from harness.files import read_toml
from harness.schema import Strict, accepted, cut, validated, where
from harness.target.domains import (ARGUMENT_HINT, Argument, Bounds, Domain, FloatArgumentFile, StrArgumentFile,
                                    argument, carried, narrowing)
from harness.target.property_types import REPLY_CODES, optional_parameters, property_types

SERVICE_KINDS = ("init", "control", "exec")
REPLY_CLASSES = ("T", "Z", "R")
NAMES_HINT = 'give a non-empty list of "module.Service"'



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

    def typed(self, raw: dict) -> dict:
        """A request's argument values as carried in JSON (harness/target/domains.py). A value of no
        declared argument is one the executive adds itself (a cancel's goal, its request id), carried
        as it is: a script's own are all declared (harness/target/script.py validates them)."""
        return {k: carried(self.args[k], v) if k in self.args else v for k, v in raw.items()}


@dataclass(frozen=True)
class Interface:
    path: str
    replies: dict[str, str]  # reply code -> class T/Z/R
    services: dict[str, Service]  # "module.Service" -> Service

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
        """What a SUT is told of the interface in the protocol's hello (docs/reference/protocol.md)."""
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
    domain: dict[str, Domain] | None = None  # VAL: argument -> bounds that also hold while a y runs
    deadline: float | None = None  # the ROS 2 types: seconds; None: derived from the golden runs


class ServiceFile(Strict):
    model_config = ConfigDict(title="a service")
    kind: Literal[SERVICE_KINDS] = Field(description=f"give one of {', '.join(SERVICE_KINDS)}")
    args: dict[str, Annotated[FloatArgumentFile | StrArgumentFile, Field(discriminator="type")]] = Field(
        default_factory=dict, description=f"give a table of name = {{ type = .. }}: {ARGUMENT_HINT}")
    until_stopped: bool = Field(False, description="give true or false")
    doc: str = ""

    @model_validator(mode="after")
    def _stoppable(self):
        if self.until_stopped and self.kind != "exec":
            raise ValueError(f"until_stopped = true on an {self.kind} service; only an exec service "
                             "may run until stopped")
        return self


class ModuleFile(Strict):
    model_config = ConfigDict(title="a module")
    doc: str = ""
    poster: str = Field("", description="give the name of the poster the module writes")  # documentation only
    services: dict[str, ServiceFile] = Field(min_length=1, description="declare the module's services: "
                                             "services.NAME = { kind = .. }")


class InterfaceFile(Strict):
    model_config = ConfigDict(title="the top level")
    replies: dict[str, Literal[REPLY_CLASSES]] = Field(
        min_length=1, description='give a [replies] table of code = "T", "Z" or "R"')
    modules: dict[str, ModuleFile] = Field(min_length=1, description="declare modules as [modules.NAME] tables")

    @model_validator(mode="after")
    def _ok_terminates(self):
        if self.replies.get("ok") != "T":
            given = f", not ok = {self.replies['ok']!r}" if "ok" in self.replies else ""
            raise ValueError(f"the reply catalogue must contain ok = \"T\"{given}")
        return self


# The keys each table of an interface description accepts (docs/reference names every one).
INTERFACE_KEYS = {m.model_config["title"]: accepted(m)
                  for m in (InterfaceFile, ModuleFile, ServiceFile, FloatArgumentFile, StrArgumentFile)}


def load_interface(path: str | Path) -> Interface:
    path = Path(path)
    data, text = read_toml(path)
    spec = validated(InterfaceFile, data, path, text)
    services = {f"{module}.{name}": Service(module, name, s.kind, {a: argument(a, v) for a, v in s.args.items()},
                                            s.until_stopped)
                for module, m in spec.modules.items() for name, s in m.services.items()}
    return Interface(str(path), dict(spec.replies), services)


class PropertyFile(Strict):
    model_config = ConfigDict(title="a property")
    id: str = Field(min_length=1, description="give every property a string id")
    family: str = Field(min_length=1, description='give a family name such as "PEX"')
    type: str = Field(description="give a type that has a template in sql/oracles/ (PC, ES, EE, EX, MX_R, MX_I, VAL, IN, OUT, RSP, CAN, GOAL, OUTLIVE)")
    x: list[str] = Field(min_length=1, description=NAMES_HINT)
    y: list[str] | None = Field(None, min_length=1, description=NAMES_HINT)
    q: list[str] | None = Field(None, min_length=1, description=NAMES_HINT)
    r_p: str | None = Field(None, description="give the rejection code the property calls for")
    z_p: str | None = Field(None, description="give the interruption code the property calls for")
    domain: dict[str, Bounds] | None = Field(None, min_length=1, description="give the bounds that hold while a y "
                                             "runs, such as { speed = { max = 0.3 } }")
    deadline: float | None = Field(None, gt=0, description="give the deadline in seconds, a number > 0, "
                                   "such as 2.5 (or leave it out: derived from the golden runs)")

    @model_validator(mode="after")
    def _parameters_of_its_type(self):
        types = property_types()
        if self.type not in types:
            raise ValueError(f"type {cut(self.type)} is not one of {', '.join(types)} (the templates of sql/oracles/)")
        needed = types[self.type]
        given = {k for k in self.model_fields_set if k not in ("id", "family", "type")}
        if given - set(needed):
            raise ValueError(f"key(s) {sorted(given - set(needed))} do not apply to type "
                             f"{self.type}; it takes {', '.join(needed)}")
        for key in needed:
            if key not in given and key not in optional_parameters()[self.type]:
                raise ValueError(f"type {self.type} needs {key!r}, which is missing")
        if "domain" in needed and (self.y is None) != (self.domain is None):
            raise ValueError(f"a state-dependent {self.type} property needs both y (the activities during which "
                             "it holds) and domain (what it allows then); give both or neither")
        return self


class PropertiesFile(Strict):
    property: list[PropertyFile] = Field(min_length=1, description="add [[property]] entries")


def load_properties(path: str | Path, interface: Interface) -> list[Property]:
    path = Path(path)
    data, text = read_toml(path)
    props, seen = [], {}
    for n, e in enumerate(validated(PropertiesFile, data, path, text).property):
        at = where(text, ("property", n))
        if e.id in seen:
            raise InputFileError(path, at, f"property id {e.id!r} is used twice (also property #{seen[e.id]}); "
                                 "ids must be unique")
        seen[e.id] = n + 1
        fields = {}
        for key in ("x", "y", "q"):
            for name in getattr(e, key) or ():
                if name not in interface.services:
                    raise InputFileError(path, where(text, ("property", n, key)),
                                         f"property {e.id!r}: {key} names {cut(name)}, which the interface "
                                         f"{interface.path} does not declare")
            fields[key] = tuple(getattr(e, key) or ())
        for key, expected in REPLY_CODES.items():
            code = getattr(e, key)
            if code is not None and interface.replies.get(code) != expected:
                raise InputFileError(path, where(text, ("property", n, key)),
                                     f"property {e.id!r}: {key} = {cut(code)} is not a class-{expected} reply "
                                     f"code of the interface {interface.path}")
            fields[key] = code
        if e.domain is not None:
            arguments = {a.name: a for x in fields["x"] for a in interface.services[x].args.values()}
            try:
                fields["domain"] = narrowing(arguments, e.domain)
            except ValueError as error:
                raise InputFileError(path, where(text, ("property", n, "domain")),
                                     f"property {e.id!r}: {error}") from None
        props.append(Property(id=e.id, family=e.family, type=e.type, deadline=e.deadline, **fields))
    return props
