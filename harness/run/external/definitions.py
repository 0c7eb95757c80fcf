"""Which systems a run or campaign tests: simulator variants, or external SUTs over `untimely/1`.

`--sut` takes comma-separated entries, each one of
- a variant of the in-process simulated layer (`genom`, `reference`, ...),
- `NAME=cmd:COMMAND`: an adapter the bench starts for every run and talks to on stdio,
- `NAME=tcp://HOST:PORT`: an adapter already listening, reached anew for every run,
- a name defined in the mission folder's `suts.toml`, where a SUT also gets its environment,
  slots (how many may run at once) and time scale.
In a command, `{python}` is the bench's own interpreter and `{root}` the repository.
"""
from __future__ import annotations

import re
import shlex
import sys
from dataclasses import asdict, dataclass, field
from pathlib import Path

from harness import ROOT
from harness.errors import InputFileError, UntimelyError
from harness.target.interface import read_toml

NAME = re.compile(r"[A-Za-z0-9][A-Za-z0-9_.-]*")
SUTS_FILE = "suts.toml"
# The transports, by the URL scheme of `--sut NAME=URL`: the key of a SUT's definition that the
# rest of the URL fills (suts.toml writes the same key), and what it reaches.
TRANSPORTS = {"cmd:": ("command", "stdio"), "tcp://": ("address", "tcp HOST:PORT")}


@dataclass(frozen=True)
class ExternalSut:
    name: str
    command: str | None = None  # stdio: started for every run
    address: str | None = None  # tcp: "HOST:PORT"
    env: dict[str, str] = field(default_factory=dict)
    slots: int = 1
    time_scale: float = 1.0
    startup_s: float = 30.0  # wall seconds for the adapter to answer hello
    probe_timeout_s: float = 3.0  # wall seconds for a pong

    def argv(self) -> list[str]:
        return [part.replace("{python}", sys.executable).replace("{root}", str(ROOT))
                for part in shlex.split(self.command)]

    def config(self) -> dict:
        return asdict(self)


KEYS = {"command": str, "address": str, "env": dict, "slots": int, "time_scale": float,
        "startup_s": float, "probe_timeout_s": float}


def _checked(name: str, spec: dict, where) -> ExternalSut:
    """An ExternalSut from a table of values; `where(key)` names the entry in messages."""
    for key, value in spec.items():
        kind = KEYS.get(key)
        if kind is None:
            raise where(key, f"unknown key {key!r}; a SUT has {', '.join(KEYS)}")
        if not (isinstance(value, kind) or kind is float and isinstance(value, int)) or isinstance(value, bool):
            raise where(key, f"{key} = {value!r}: give a {kind.__name__}")
    if sum(key in spec for key, _ in TRANSPORTS.values()) != 1:
        raise where(next(iter(TRANSPORTS.values()))[0], "give exactly one of " + " or ".join(
            f"{key} ({what})" for key, what in TRANSPORTS.values()))
    if "address" in spec and not re.fullmatch(r"[^:\s]+:\d+", spec["address"]):
        raise where("address", f"address = {spec['address']!r}: give HOST:PORT, e.g. 127.0.0.1:7400")
    if "command" in spec and not shlex.split(spec["command"]):
        raise where("command", "command is empty: give the adapter's command line")
    for key in ("slots", "time_scale", "startup_s", "probe_timeout_s"):
        if key in spec and not spec[key] > 0:
            raise where(key, f"{key} = {spec[key]!r}: give a number > 0")
    if not all(isinstance(v, str) for v in spec.get("env", {}).values()):
        raise where("env", f"env = {spec['env']!r}: give text values")
    return ExternalSut(name, **{k: float(v) if KEYS[k] is float else v for k, v in spec.items()})


def load_suts_file(path: Path) -> dict[str, ExternalSut]:
    if not path.exists():
        return {}
    suts = {}
    for name, spec in read_toml(path).items():
        def where(key, problem, name=name):
            return InputFileError(path, f"[{name}] {key}", problem)
        if not NAME.fullmatch(name) or not isinstance(spec, dict):
            raise InputFileError(path, f"[{name}]", "a SUT is a table named by letters, digits, '_', '.' or '-'")
        suts[name] = _checked(name, spec, where)
    return suts


def resolve(option: str, mission: Path, time_scale: float | None = None) -> tuple[list[str], dict[str, ExternalSut]]:
    """The SUT names of a `--sut` option, in order, and the external ones' definitions;
    `time_scale` (the --time-scale option) overrides the definitions' own."""
    names, external = [], {}
    defined = load_suts_file(mission / SUTS_FILE)
    for entry in (e.strip() for e in option.split(",")):
        name, _, target = entry.partition("=")
        if not NAME.fullmatch(name) or name in names:
            raise UntimelyError(f"--sut {option!r}: {entry!r} is not a new SUT name; give distinct "
                                "comma-separated entries, e.g. genom,bip-a or toy=cmd:COMMAND")
        if target:
            def where(key, problem, entry=entry):
                return UntimelyError(f"--sut {entry!r}: {problem}")
            scheme = next((s for s in TRANSPORTS if target.startswith(s)), None)
            if scheme is None:
                raise UntimelyError(f"--sut {entry!r}: write NAME=cmd:COMMAND or NAME=tcp://HOST:PORT")
            external[name] = _checked(name, {TRANSPORTS[scheme][0]: target[len(scheme):]}, where)
        elif name in defined:
            external[name] = defined[name]
        names.append(name)
    if time_scale is not None:
        if not time_scale > 0:
            raise UntimelyError(f"--time-scale {time_scale}: give a factor > 0 (1 = real time)")
        external = {n: ExternalSut(**{**s.config(), "time_scale": time_scale}) for n, s in external.items()}
    return names, external
