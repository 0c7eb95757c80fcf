"""Which systems a run or campaign tests: simulator variants, or external SUTs over `untimely/1`.

`--sut` takes comma-separated entries, each one of
- a variant of the in-process simulated layer (`genom`, `reference`, ...),
- `NAME=cmd:COMMAND`: an adapter the bench starts for every run and talks to on stdio,
- `NAME=tcp://HOST:PORT`: an adapter already listening, reached anew for every run,
- a name defined in the mission folder's `suts.toml`, where a SUT also gets its environment,
  slots (how many may run at once) and time scale; its command starts in that folder, so it
  may name the adapter relative to it.
In a command, `{python}` is the bench's own interpreter, `{root}` the folder holding the
harness package (the repository in a checkout) and, in suts.toml, `{mission}` the mission folder.
"""
from __future__ import annotations

import re
import shlex
import sys
from pathlib import Path

from pydantic import ConfigDict, Field, model_validator

from harness import ROOT, current_modules
from harness.errors import InputFileError, UntimelyError
from harness.files import read_toml
from harness.schema import Strict, accepted, cut, validated, where
from harness.target.mission import SUTS_FILE

NAME = re.compile(r"[A-Za-z0-9][A-Za-z0-9_.-]*")
# The transports, by the URL scheme of `--sut NAME=URL`: the key of a SUT's definition that the
# rest of the URL fills (suts.toml writes the same key), and what it reaches.
TRANSPORTS = {"cmd:": ("command", "stdio"), "tcp://": ("address", "tcp HOST:PORT")}


class SutTable(Strict):
    model_config = ConfigDict(title="a SUT")
    command: str | None = Field(None, description="give the adapter's command line")
    address: str | None = Field(None, pattern=r"^[^:\s]+:\d+$", description="give HOST:PORT, e.g. 127.0.0.1:7400")
    env: dict[str, str] = Field({}, description="give a table of NAME = \"text\"")
    slots: int = Field(1, gt=0, description="give a whole number > 0")
    time_scale: float = Field(1.0, gt=0, description="give a number > 0 (mission seconds per wall second)")
    startup_s: float = Field(30.0, gt=0, description="give a number of wall seconds > 0")
    probe_timeout_s: float = Field(3.0, gt=0, description="give a number of wall seconds > 0")

    @model_validator(mode="after")
    def _one_transport(self):
        if sum(getattr(self, key) is not None for key, _ in TRANSPORTS.values()) != 1:
            raise ValueError("give exactly one of " + " or ".join(f"{key} ({what})" for key, what in TRANSPORTS.values()))
        if self.command is not None:
            try:
                words = shlex.split(self.command)
            except ValueError as e:  # an unclosed quote
                raise ValueError(f"command = {cut(self.command)}: {e}; close the quote") from None
            if not words:
                raise ValueError("command is empty: give the adapter's command line")
        return self


class ExternalSut(SutTable):
    """A SUT reached over `untimely/1`: a table of `suts.toml` (or a `--sut NAME=URL`) with its name,
    and the folder its command starts in; the fields and their defaults are SutTable's."""
    # Not strict: it is also rebuilt from the JSON of campaigns.config, where a number may be an int.
    model_config = ConfigDict(title="a SUT", strict=False)
    name: str
    cwd: str | None = None  # where the command starts: the target folder of a suts.toml entry

    def __init__(self, name: str | None = None, /, **fields):
        # ExternalSut("toy", command=...) reads as the dataclass it was; a stored config gives name=.
        super().__init__(**fields if name is None else {"name": name, **fields})

    def argv(self) -> list[str]:
        """The command's words, placeholders filled in; a module it names by a name from before
        harness/sut/ runs under its current name (a store's recorded command, an older suts.toml)."""
        return [part.replace("{python}", sys.executable).replace("{root}", str(ROOT))
                for part in shlex.split(current_modules(self.command))]

    def config(self) -> dict:
        """Its fields as stored in campaigns.config, name first (`cwd` only when set: older stores lack it)."""
        fields = self.model_dump(exclude={"name", "cwd"} if self.cwd is None else {"name"})
        return {"name": self.name, **fields}


def from_configs(configs: dict[str, dict]) -> dict[str, ExternalSut]:
    """The external SUTs a campaign's record stores, by name (the inverse of ExternalSut.config)."""
    return {name: ExternalSut(**config) for name, config in configs.items()}


KEYS = accepted(SutTable)  # the keys of a SUT's table (docs/reference names every one)


def _checked(name: str, spec, path, text: str | None = None) -> ExternalSut:
    """An ExternalSut from a table of values read from `path` (a file, or the --sut option)."""
    table = validated(SutTable, spec, path, text, at=(name,) if text is not None else ())
    return ExternalSut(name, **table.model_dump())


def load_suts_file(path: Path) -> dict[str, ExternalSut]:
    if not path.exists():
        return {}
    data, text = read_toml(path)
    suts = {}
    for name, spec in data.items():
        if not NAME.fullmatch(name) or not isinstance(spec, dict):
            raise InputFileError(path, where(text, (name,)), f"{cut(name)}: a SUT is a table named by letters, "
                                 "digits, '_', '.' or '-'")
        if isinstance(spec.get("command"), str):
            spec = {**spec, "command": spec["command"].replace("{mission}", shlex.quote(str(path.parent.resolve())))}
        sut = _checked(name, spec, path, text)
        suts[name] = sut.model_copy(update={"cwd": str(path.parent.resolve())}) if sut.command else sut
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
            scheme = next((s for s in TRANSPORTS if target.startswith(s)), None)
            if scheme is None:
                raise UntimelyError(f"--sut {entry!r}: write NAME=cmd:COMMAND or NAME=tcp://HOST:PORT")
            external[name] = _checked(name, {TRANSPORTS[scheme][0]: target[len(scheme):]}, f"--sut {entry!r}")
        elif name in defined:
            external[name] = defined[name]
        names.append(name)
    if time_scale is not None:  # checked > 0 by the command line
        external = {n: s.model_copy(update={"time_scale": time_scale}) for n, s in external.items()}
    return names, external
